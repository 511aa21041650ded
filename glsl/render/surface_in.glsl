// What surface.vert hands every fragment shader, and the normal facing the viewer.
#pragma once

in vec3 v_position;  // world space, m
in vec3 v_normal;    // world space, interpolated (not unit)
in vec2 v_uv;

// Cloth is seen from both sides: a back face shows the other side, whose normal points the other way.
vec3 facingNormal(vec3 n) {
  return gl_FrontFacing ? n : -n;
}
