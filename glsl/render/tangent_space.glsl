// Height-map bump mapping in the tangent frame, as CS184 defines it: with h(u, v) the height map,
//   dU = (h(u + 1/w, v) - h(u, v)) * kh * kn,  dV = (h(u, v + 1/h) - h(u, v)) * kh * kn,
//   n_object = (-dU, -dV, 1), n_world = TBN * n_object.
#pragma once

in vec4 v_tangent;  // xyz: world-space tangent along +u; w: bitangent sign

uniform sampler2D u_height_map;
uniform float u_height_scaling;  // kh
uniform float u_normal_scaling;  // kn

vec3 bumpedNormal(vec3 n_geometric, vec2 uv) {
  vec3 n = normalize(n_geometric);
  // Gram-Schmidt: interpolation leaves the tangent slightly off the normal's plane.
  vec3 t = normalize(v_tangent.xyz - dot(v_tangent.xyz, n) * n);
  vec3 b = (v_tangent.w < 0.0 ? -1.0 : 1.0) * cross(n, t);
  vec2 texel = 1.0 / vec2(textureSize(u_height_map, 0));
  float h = texture(u_height_map, uv).r;
  float du = (texture(u_height_map, uv + vec2(texel.x, 0.0)).r - h) * u_height_scaling * u_normal_scaling;
  float dv = (texture(u_height_map, uv + vec2(0.0, texel.y)).r - h) * u_height_scaling * u_normal_scaling;
  return normalize(mat3(t, b, n) * vec3(-du, -dv, 1.0));
}
