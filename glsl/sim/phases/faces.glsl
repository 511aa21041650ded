// The face contacts of one point (CpuSolver::collideFaces, docs/contact.md): the cloth's edges and triangles
// that have the point as an end or corner, against the sharp convex edges and corners of each mesh that has
// them, found in a uniform grid by the cell of the edge's middle or the triangle's centroid. Jacobi: every
// position read is from before the pass (neighbour(j), the storage's), and the point gathers its own shares
// of the contacts it is part of, edges first (ascending), then triangles (ascending), mesh after mesh, each
// cell's features ascending; the other ends of a contact compute it alike from the same positions, so no
// point writes another's. The tables: gpu::faceTables (src/gpu/face_tables.cpp), layout.h's kFace*.
#pragma once

#include "../common.glsl"
#include "../physics.glsl"

layout(std430, binding = kBindingFaceTable) readonly buffer FaceTableBuffer {
  uint faceTable[];
};
// Per mesh: (grid origin, 1 / cell), (thickness, 0, 0, 0); its edges, 4 vec4s each: (a, mid.x), (b, mid.y),
// (n1, mid.z), (n2, half its length); its corners, 2 each: (p, 0), (normal, 0).
layout(std430, binding = kBindingFaceFeatures) readonly buffer FaceFeaturesBuffer {
  vec4 faceFeatures[];
};

const float kThird = 0.3333333432674407958984375;  // float(1.0 / 3.0), as CpuSolver<float> rounds it

// The feature grid's cell of `at`, if inside the grid (written so that NaN fails).
bool featureCell(vec3 at, vec3 origin, float inv_cell, uvec3 dims, out uint cell) {
  precise vec3 c = floor((at - origin) * inv_cell);
  cell = 0u;
  if (!(c.x >= 0.0 && c.y >= 0.0 && c.z >= 0.0 && c.x < float(dims.x) && c.y < float(dims.y) && c.z < float(dims.z)))
    return false;
  uvec3 k = uvec3(ivec3(c));
  cell = (k.z * dims.y + k.y) * dims.x + k.x;
  return true;
}

// The point's mean share of its face contacts (zero if none).
vec3 faceCorrection(uint i) {
  precise vec3 sum = vec3(0.0);
  int count = 0;
  uint meshes = faceTable[kFaceMeshes];
  uint edge_start = faceTable[kFaceEdgeStart], point_edges = faceTable[kFacePointEdges];
  uint edges = faceTable[kFaceEdges];
  uint triangle_start = faceTable[kFaceTriangleStart], point_triangles = faceTable[kFacePointTriangles];
  uint triangles = faceTable[kFaceTriangles];
  for (uint m = 0u; m < meshes; ++m) {
    uint h = kFaceHeaderWords + kFaceMeshWords * m;
    uint grid_edge_start = faceTable[h + kFaceGridEdgeStart], grid_edges = faceTable[h + kFaceGridEdges];
    uint grid_corner_start = faceTable[h + kFaceGridCornerStart], grid_corners = faceTable[h + kFaceGridCorners];
    uvec3 dims =
        uvec3(faceTable[h + kFaceGridDims], faceTable[h + kFaceGridDims + 1u], faceTable[h + kFaceGridDims + 2u]);
    uint header = faceTable[h + kFaceFeatureHeader];
    uint feature_edges = faceTable[h + kFaceFeatureEdges], feature_corners = faceTable[h + kFaceFeatureCorners];
    vec4 g0 = faceFeatures[header];
    float thickness = faceFeatures[header + 1u].x;
    for (uint k = faceTable[edge_start + i]; k < faceTable[edge_start + i + 1u]; ++k) {
      uint e = faceTable[point_edges + k];
      uint a = faceTable[edges + 2u * e], b = faceTable[edges + 2u * e + 1u];
      vec4 na = neighbour(a), nb = neighbour(b);
      if (isPinned(na) || isPinned(nb)) continue;  // the pin has the last word (CpuSolver::collideFaces says why)
      vec3 xa = na.xyz, xb = nb.xyz;
      precise vec3 mid = (xa + xb) * 0.5;
      uint cell;
      if (!featureCell(mid, g0.xyz, g0.w, dims, cell)) continue;
      precise float half_length = 0.5 * length3(xa - xb);
      for (uint f = faceTable[grid_edge_start + cell]; f < faceTable[grid_edge_start + cell + 1u]; ++f) {
        uint at = feature_edges + 4u * faceTable[grid_edges + f];
        vec4 fa = faceFeatures[at], fb = faceFeatures[at + 1u], fn1 = faceFeatures[at + 2u],
             fn2 = faceFeatures[at + 3u];
        if (farApart(mid, half_length, vec3(fa.w, fb.w, fn1.w), fn2.w, thickness)) continue;
        float s;
        vec3 move;
        if (edgeContact(xa, xb, fa.xyz, fb.xyz, fn1.xyz, fn2.xyz, thickness, s, move)) {
          sum += edgeShare(s, i == b, move);
          ++count;
        }
      }
    }
    for (uint k = faceTable[triangle_start + i]; k < faceTable[triangle_start + i + 1u]; ++k) {
      uint t = faceTable[point_triangles + k];
      uint i0 = faceTable[triangles + 3u * t], i1 = faceTable[triangles + 3u * t + 1u],
           i2 = faceTable[triangles + 3u * t + 2u];
      vec4 n0 = neighbour(i0), n1 = neighbour(i1), n2 = neighbour(i2);
      if (isPinned(n0) || isPinned(n1) || isPinned(n2)) continue;
      vec3 p0 = n0.xyz, p1 = n1.xyz, p2 = n2.xyz;
      precise vec3 centre = (p0 + p1 + p2) * kThird;
      uint cell;
      if (!featureCell(centre, g0.xyz, g0.w, dims, cell)) continue;
      int corner = i == i0 ? 0 : i == i1 ? 1 : 2;
      precise float radius = sqrt(
          max(max(dot3(p0 - centre, p0 - centre), dot3(p1 - centre, p1 - centre)), dot3(p2 - centre, p2 - centre)));
      for (uint f = faceTable[grid_corner_start + cell]; f < faceTable[grid_corner_start + cell + 1u]; ++f) {
        uint at = feature_corners + 2u * faceTable[grid_corners + f];
        vec3 fp = faceFeatures[at].xyz, fnormal = faceFeatures[at + 1u].xyz;
        if (farApart(centre, radius, fp, 0.0, thickness)) continue;
        vec3 bary, move;
        if (cornerContact(p0, p1, p2, fp, fnormal, thickness, bary, move)) {
          sum += cornerShare(bary, corner, move);
          ++count;
        }
      }
    }
  }
  precise vec3 c = count > 0 ? sum / float(count) : vec3(0.0);
  return c;
}
