#include "gpu/face_tables.hpp"

#include "core/mesh_features.hpp"
#include "gpu/layout.hpp"

#include <stdexcept>

namespace drape::gpu {

namespace {

// Appends `v` to the table and returns where it starts.
std::uint32_t append(std::vector<std::uint32_t>& table, const std::vector<std::uint32_t>& v) {
  if (table.size() + v.size() >= (std::uint64_t(1) << 32)) throw std::length_error("face contacts: tables too large");
  const auto at = std::uint32_t(table.size());
  table.insert(table.end(), v.begin(), v.end());
  return at;
}

}  // namespace

FaceTables faceTables(const Scene& scene, const Topology& topo) {
  FaceTables out;
  if (scene.meshes.empty() || topo.triangles.empty()) return out;
  const FaceAdjacency faces = buildFaceAdjacency(topo);
  struct Kept {
    MeshFeatures features;
    FeatureGrid grid;
    float thickness;
  };
  std::vector<Kept> kept;
  for (const MeshSpec& m : scene.meshes) {
    MeshFeatures f = contactFeatures(scene, m);
    if (f.edges.empty() && f.corners.empty()) continue;  // CpuSolver skips its empty grid
    const double thickness = meshThickness(scene.cloth, m);
    FeatureGrid grid = buildFeatureGrid(f, featureReach(thickness, faces));
    if (grid.edge_start.empty()) continue;
    kept.push_back({std::move(f), std::move(grid), float(thickness)});
  }
  if (kept.empty()) return out;
  out.meshes = int(kept.size());
  std::vector<std::uint32_t>& t = out.table;
  t.assign(kFaceHeaderWords + kFaceMeshWords * kept.size(), 0u);
  t[kFaceMeshes] = std::uint32_t(kept.size());
  t[kFaceEdgeStart] = append(t, faces.edge_start);
  t[kFacePointEdges] = append(t, faces.point_edges);
  t[kFaceEdges] = append(t, faces.edges);
  t[kFaceTriangleStart] = append(t, faces.triangle_start);
  t[kFacePointTriangles] = append(t, faces.point_triangles);
  t[kFaceTriangles] = append(t, topo.triangles);
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const Kept& m = kept[k];
    const std::size_t h = kFaceHeaderWords + kFaceMeshWords * k;
    t[h + kFaceGridEdgeStart] = append(t, m.grid.edge_start);
    t[h + kFaceGridEdges] = append(t, m.grid.edges);
    t[h + kFaceGridCornerStart] = append(t, m.grid.corner_start);
    t[h + kFaceGridCorners] = append(t, m.grid.corners);
    t[h + kFaceGridDims + 0] = std::uint32_t(m.grid.dims.x);
    t[h + kFaceGridDims + 1] = std::uint32_t(m.grid.dims.y);
    t[h + kFaceGridDims + 2] = std::uint32_t(m.grid.dims.z);
    // Rounded once from double, as CpuSolver<float>::buildFaceContacts rounds them.
    t[h + kFaceFeatureHeader] = std::uint32_t(out.features.size());
    out.features.emplace_back(m.grid.origin_f, m.grid.inv_cell_f);
    out.features.emplace_back(m.thickness, 0.0f, 0.0f, 0.0f);
    t[h + kFaceFeatureEdges] = std::uint32_t(out.features.size());
    for (const FeatureEdge& e : m.features.edges) {
      const glm::vec3 mid(0.5 * (e.a + e.b));
      out.features.emplace_back(glm::vec3(e.a), mid.x);
      out.features.emplace_back(glm::vec3(e.b), mid.y);
      out.features.emplace_back(glm::vec3(e.normal_a), mid.z);
      out.features.emplace_back(glm::vec3(e.normal_b), float(0.5 * glm::distance(e.a, e.b)));
    }
    t[h + kFaceFeatureCorners] = std::uint32_t(out.features.size());
    for (const FeatureCorner& c : m.features.corners) {
      out.features.emplace_back(glm::vec3(c.p), 0.0f);
      out.features.emplace_back(glm::vec3(c.normal), 0.0f);
    }
  }
  return out;
}

}  // namespace drape::gpu
