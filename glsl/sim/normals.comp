// Per-vertex normals and tangents for the renderer: a gather over the triangles around each vertex
// (CSR lists built once on the host), so no atomics and a fixed summation order. Normals are area
// weighted (the cross product of two edges is twice the triangle's area along its normal); tangents
// follow +u of the texture coordinates (Lengyel 2001), made orthogonal to the normal, with the
// bitangent's handedness in w. Reads the current positions bound at kBindingPosIn.
#include "common.glsl"

layout(local_size_x = kLocalSize) in;

layout(std430, binding = kBindingNormals) writeonly buffer NormalsBuffer {
  vec4 normals[];
};
layout(std430, binding = kBindingTangents) writeonly buffer TangentsBuffer {
  vec4 tangents[];
};
layout(std430, binding = kBindingVertexTriOffsets) readonly buffer VertexTriOffsetsBuffer {
  uint vertexTriOffsets[];
};
layout(std430, binding = kBindingVertexTris) readonly buffer VertexTrisBuffer {
  uint vertexTris[];
};
layout(std430, binding = kBindingTriangles) readonly buffer TrianglesBuffer {
  uint triangles[];
};
layout(std430, binding = kBindingUvs) readonly buffer UvsBuffer {
  vec2 uvs[];
};

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  vec3 n = vec3(0.0), t = vec3(0.0), b = vec3(0.0);
  for (uint k = vertexTriOffsets[i]; k < vertexTriOffsets[i + 1u]; ++k) {
    uint tri = vertexTris[k];
    uint i0 = triangles[3u * tri], i1 = triangles[3u * tri + 1u], i2 = triangles[3u * tri + 2u];
    vec3 p0 = posIn[i0].xyz;
    vec3 e1 = posIn[i1].xyz - p0, e2 = posIn[i2].xyz - p0;
    vec2 d1 = uvs[i1] - uvs[i0], d2 = uvs[i2] - uvs[i0];
    n += cross(e1, e2);
    // The tangent frame without dividing by the uv determinant, only its sign: every triangle then
    // counts in proportion to its size, like the normals.
    float s = d1.x * d2.y - d2.x * d1.y < 0.0 ? -1.0 : 1.0;
    t += s * (e1 * d2.y - e2 * d1.y);
    b += s * (e2 * d1.x - e1 * d2.x);
  }
  float len = length(n);
  n = len > 0.0 ? n / len : vec3(0.0, 1.0, 0.0);
  t -= n * dot(n, t);
  float tlen = length(t);
  t = tlen > 0.0 ? t / tlen : normalize(cross(n, abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0)));
  float handedness = dot(cross(n, t), b) < 0.0 ? -1.0 : 1.0;
  normals[i] = vec4(n, 0.0);
  tangents[i] = vec4(t, handedness);
}
