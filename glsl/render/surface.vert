// Every surface (cloth, sphere, plane) by vertex pulling: gl_VertexID is the index from the element
// buffer, and the attributes come from storage buffers, so the cloth is drawn straight from the
// solver's buffers without a vertex-array copy. The cloth's vertices past its points are its quads'
// centres, which the surface pass (cloth_surface.comp) places; its normals, tangents and UVs cover both.
//   TANGENT_SPACE  pass the tangent on (bump and displacement)
//   DISPLACE       move each vertex along its normal by the height map (displacement)
//   SHADOW_RECEIVER  pass the position in the light's clip space on (shadow)
//   DEPTH_ONLY     position only (shadow-map pass)
#include "render_bindings.h"

layout(std430, binding = RENDER_BINDING_POSITIONS) readonly buffer Positions {
  vec4 positions[];
};
layout(std430, binding = RENDER_BINDING_CENTRES) readonly buffer Centres {
  vec4 centres[];
};

// The solver's blow-up flags, read on the GPU: a cloth whose flags are raised is not drawn, so no frame of
// garbage reaches the screen while the host learns of it a frame late (Solver::recentHealth). Colliders
// and the CPU solvers' uploads bind a buffer of zeros.
layout(std430, binding = RENDER_BINDING_HEALTH) readonly buffer ClothHealth {
  uint health_flags;
};

uniform mat4 u_model;
uniform mat4 u_view_projection;
uniform uint u_point_count;  // vertices from here on are quad centres (the cloth's; no collider has any)

#ifndef DEPTH_ONLY
layout(std430, binding = RENDER_BINDING_NORMALS) readonly buffer Normals {
  vec4 normals[];
};
layout(std430, binding = RENDER_BINDING_UVS) readonly buffer Uvs {
  vec2 uvs[];
};
uniform mat3 u_normal_matrix;
out vec3 v_position;
out vec3 v_normal;
out vec2 v_uv;
#endif

#ifdef TANGENT_SPACE
layout(std430, binding = RENDER_BINDING_TANGENTS) readonly buffer Tangents {
  vec4 tangents[];
};
out vec4 v_tangent;
#endif

#ifdef DISPLACE
uniform sampler2D u_height_map;
uniform float u_height_scaling;
#endif

#ifdef SHADOW_RECEIVER
uniform mat4 u_light_view_projection;
out vec4 v_light_clip;
#endif

void main() {
  uint i = uint(gl_VertexID);
  vec3 position = i < u_point_count ? positions[i].xyz : centres[i - u_point_count].xyz;
  vec4 world = u_model * vec4(position, 1.0);
#ifndef DEPTH_ONLY
  vec3 n = normalize(u_normal_matrix * normals[i].xyz);
  v_uv = uvs[i];
#ifdef DISPLACE
  // Level 0: a vertex has no screen-space derivatives to choose a mip level from.
  world.xyz += n * textureLod(u_height_map, v_uv, 0.0).r * u_height_scaling;
#endif
  v_position = world.xyz;
  v_normal = n;
#endif
#ifdef TANGENT_SPACE
  v_tangent = vec4(normalize(mat3(u_model) * tangents[i].xyz), tangents[i].w);
#endif
#ifdef SHADOW_RECEIVER
  v_light_clip = u_light_view_projection * world;
#endif
  gl_Position = u_view_projection * world;
  // Every vertex beyond the same clip plane: each triangle is rejected whole.
  if (health_flags != 0u) gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
}
