// Lighting is computed on linear radiance; colours the user picks and the colour textures are in the
// display's (sRGB) encoding. A gamma of 2.2 stands in for the exact sRGB curve.
#pragma once

vec3 toLinear(vec3 display_colour) {
  return pow(max(display_colour, vec3(0.0)), vec3(2.2));
}
vec3 toDisplay(vec3 radiance) {
  return pow(clamp(radiance, vec3(0.0), vec3(1.0)), vec3(1.0 / 2.2));
}
