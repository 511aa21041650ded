// The cloth's surface for drawing, from its positions alone (render/cloth_surface.hpp says why; the CPU
// reference, computeSurface, does the same maths). Two passes, one dispatch each:
//   (default)  per point: the sum of its faces' normals and UV tangents (a quad's from its diagonals),
//              made orthonormal, the bitangent's handedness in w
//   CENTRES    per quad: its centre vertex on the diagonal it folds along, with the corners' normals and
//              tangents weighted the same way (reads what the first pass wrote)
#include "render_bindings.h"

layout(local_size_x = RENDER_SURFACE_LOCAL_SIZE) in;

layout(std430, binding = RENDER_BINDING_POSITIONS) readonly buffer Positions {
  vec4 positions[];
};
layout(std430, binding = RENDER_BINDING_NORMALS) buffer Normals {
  vec4 normals[];
};
layout(std430, binding = RENDER_BINDING_TANGENTS) buffer Tangents {
  vec4 tangents[];
};
layout(std430, binding = RENDER_BINDING_UVS) readonly buffer Uvs {
  vec2 uvs[];
};
layout(std430, binding = RENDER_BINDING_FACES) readonly buffer Faces {
  uvec4 faces[];
};

uniform uint u_point_count;
uniform uint u_quad_count;

struct FaceFrame {
  vec3 normal, tangent, bitangent;
};

// Twice the face's area along its normal, and dP/du, dP/dv scaled by its size (only the UV determinant's
// sign is used), so every face counts in proportion to its size.
FaceFrame faceFrame(uvec4 f) {
  bool quad = f.w != RENDER_NO_CORNER;
  uint a = f.x, b = quad ? f.z : f.y, c = quad ? f.y : f.x, d = quad ? f.w : f.z;
  vec3 e1 = positions[b].xyz - positions[a].xyz, e2 = positions[d].xyz - positions[c].xyz;
  vec2 d1 = uvs[b] - uvs[a], d2 = uvs[d] - uvs[c];
  float s = d1.x * d2.y - d2.x * d1.y < 0.0 ? -1.0 : 1.0;
  FaceFrame frame;
  frame.normal = cross(e1, e2);
  frame.tangent = s * (e1 * d2.y - e2 * d1.y);
  frame.bitangent = s * (e2 * d1.x - e1 * d2.x);
  return frame;
}

void writeFrame(uint vertex, vec3 n, vec3 t, vec3 b) {
  float n_len = length(n);
  n = n_len > 0.0 ? n / n_len : vec3(0.0, 1.0, 0.0);
  t -= n * dot(n, t);
  float t_len = length(t);
  t = t_len > 0.0 ? t / t_len : normalize(cross(n, abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0)));
  normals[vertex] = vec4(n, 0.0);
  tangents[vertex] = vec4(t, dot(cross(n, t), b) < 0.0 ? -1.0 : 1.0);
}

#ifndef CENTRES

layout(std430, binding = RENDER_BINDING_FACE_OFFSETS) readonly buffer FaceOffsets {
  uint face_offsets[];
};
layout(std430, binding = RENDER_BINDING_POINT_FACES) readonly buffer PointFaces {
  uint point_faces[];
};

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_point_count) return;
  vec3 n = vec3(0.0), t = vec3(0.0), b = vec3(0.0);
  for (uint k = face_offsets[i]; k < face_offsets[i + 1u]; ++k) {
    FaceFrame f = faceFrame(faces[point_faces[k]]);
    n += f.normal;
    t += f.tangent;
    b += f.bitangent;
  }
  writeFrame(i, n, t, b);
}

#else

layout(std430, binding = RENDER_BINDING_CENTRES) writeonly buffer Centres {
  vec4 centres[];
};
layout(std430, binding = RENDER_BINDING_QUAD_REST) readonly buffer QuadRest {
  vec2 quad_rest[];
};

const float kCreaseBlend = 0.02;  // cloth_surface.hpp

void main() {
  uint q = gl_GlobalInvocationID.x;
  if (q >= u_quad_count) return;
  uvec4 c = faces[q];
  vec3 x0 = positions[c.x].xyz, x1 = positions[c.y].xyz, x2 = positions[c.z].xyz, x3 = positions[c.w].xyz;
  vec2 rest = quad_rest[q];
  // The diagonal that kept more of its length is the one the quad folds along.
  float w = smoothstep(-kCreaseBlend, kCreaseBlend, distance(x0, x2) / rest.x - distance(x1, x3) / rest.y);
  centres[q] = vec4(0.5 * (w * (x0 + x2) + (1.0 - w) * (x1 + x3)), 1.0);
  vec3 n = w * (normals[c.x].xyz + normals[c.z].xyz) + (1.0 - w) * (normals[c.y].xyz + normals[c.w].xyz);
  vec3 t = w * (tangents[c.x].xyz + tangents[c.z].xyz) + (1.0 - w) * (tangents[c.y].xyz + tangents[c.w].xyz);
  FaceFrame face = faceFrame(c);
  writeFrame(u_point_count + q, length(n) > 0.0 ? n : face.normal, t, face.bitangent);
}

#endif
