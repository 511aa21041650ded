#include "core/mesh_features.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace drape {

namespace {

glm::dvec3 faceNormal(const MeshObstacle& m, std::size_t t) {
  const glm::dvec3 a = m.positions[m.triangles[3 * t]], b = m.positions[m.triangles[3 * t + 1]],
                   c = m.positions[m.triangles[3 * t + 2]];
  return glm::normalize(glm::cross(b - a, c - a));
}

// The angle of triangle t at its corner `corner` (0, 1, 2), for the angle-weighted normal.
double cornerAngle(const MeshObstacle& m, std::size_t t, int corner) {
  const glm::dvec3 p = m.positions[m.triangles[3 * t + std::size_t(corner)]];
  const glm::dvec3 u = m.positions[m.triangles[3 * t + std::size_t((corner + 1) % 3)]] - p;
  const glm::dvec3 v = m.positions[m.triangles[3 * t + std::size_t((corner + 2) % 3)]] - p;
  return std::acos(std::clamp(glm::dot(glm::normalize(u), glm::normalize(v)), -1.0, 1.0));
}

}  // namespace

MeshFeatures findFeatures(const MeshObstacle& mesh, double min_angle_degrees) {
  // Each undirected edge and the (one or two) triangles on it. buildMeshObstacle checked that every edge
  // of the polygon faces is in exactly two faces; a polygon's fan diagonals are in two triangles of one
  // (flat) face, so they are never features.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> faces;
  const std::size_t triangles = mesh.triangles.size() / 3;
  for (std::size_t t = 0; t < triangles; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = mesh.triangles[3 * t + std::size_t(k)],
                          b = mesh.triangles[3 * t + std::size_t((k + 1) % 3)];
      faces[{std::min(a, b), std::max(a, b)}].push_back(std::uint32_t(t));
    }
  const double min_cos = std::cos(glm::radians(min_angle_degrees));
  MeshFeatures out;
  std::map<std::uint32_t, std::uint32_t> corner_of;  // vertex -> corner index, in order of first use
  std::vector<std::uint32_t> corner_vertices;
  for (const auto& [edge, tris] : faces) {
    if (tris.size() != 2) continue;
    const glm::dvec3 n1 = faceNormal(mesh, tris[0]), n2 = faceNormal(mesh, tris[1]);
    if (glm::dot(n1, n2) > min_cos) continue;
    // Convex: the third corner of the second triangle lies below the first's plane.
    std::uint32_t far = 0;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.triangles[3 * tris[1] + std::size_t(k)];
      if (v != edge.first && v != edge.second) far = v;
    }
    if (glm::dot(mesh.positions[far] - mesh.positions[edge.first], n1) >= 0.0) continue;
    out.edges.push_back({mesh.positions[edge.first], mesh.positions[edge.second], n1, n2});
    for (std::uint32_t v : {edge.first, edge.second})
      if (corner_of.emplace(v, std::uint32_t(corner_vertices.size())).second) corner_vertices.push_back(v);
  }
  // Angle-weighted normals of the corners.
  std::vector<glm::dvec3> sum(corner_vertices.size(), glm::dvec3(0.0));
  for (std::size_t t = 0; t < triangles; ++t)
    for (int k = 0; k < 3; ++k) {
      const auto it = corner_of.find(mesh.triangles[3 * t + std::size_t(k)]);
      if (it != corner_of.end()) sum[it->second] += cornerAngle(mesh, t, k) * faceNormal(mesh, t);
    }
  for (std::size_t c = 0; c < corner_vertices.size(); ++c)
    out.corners.push_back({mesh.positions[corner_vertices[c]], glm::normalize(sum[c])});
  return out;
}

FeatureGrid buildFeatureGrid(const MeshFeatures& features, double reach) {
  FeatureGrid g;
  g.cell = reach;
  if (features.edges.empty() && features.corners.empty()) return g;
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const FeatureEdge& e : features.edges) {
    lo = glm::min(lo, glm::min(e.a, e.b));
    hi = glm::max(hi, glm::max(e.a, e.b));
  }
  for (const FeatureCorner& c : features.corners) {
    lo = glm::min(lo, c.p);
    hi = glm::max(hi, c.p);
  }
  g.origin = lo - reach;
  // Cells of `reach`, unless the features' box would need more than kMaxFeatureCells of them (an obstacle
  // kilometres across, or one scaled past any scene's size: its count overflowed): then the cell doubles
  // until they fit. A cell wider than the reach lists more features, and the lookup still reads one cell.
  const glm::dvec3 span = hi - lo + 2.0 * reach;
  auto cellsOf = [&](double cell) {
    const glm::dvec3 d = glm::floor(span / cell) + 1.0;
    return d.x * d.y * d.z;
  };
  while (!(cellsOf(g.cell) <= kMaxFeatureCells))
    g.cell *= 2.0;
  g.dims = glm::ivec3(glm::floor(span / g.cell)) + 1;
  g.origin_f = glm::vec3(g.origin);
  g.inv_cell_f = float(1.0 / g.cell);
  const std::size_t cells = std::size_t(g.dims.x) * std::size_t(g.dims.y) * std::size_t(g.dims.z);
  // Each feature in every cell whose box is within reach of the feature's box (a superset of "within reach
  // of the feature", which is all the lookup needs).
  auto fill = [&](std::size_t count, auto box, std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& items) {
    start.assign(cells + 1, 0);
    auto each = [&](auto add) {
      for (std::size_t f = 0; f < count; ++f) {
        glm::dvec3 flo, fhi;
        box(f, flo, fhi);
        const glm::ivec3 from = glm::max(glm::ivec3(glm::floor((flo - reach - g.origin) / g.cell)), glm::ivec3(0));
        const glm::ivec3 to = glm::min(glm::ivec3(glm::floor((fhi + reach - g.origin) / g.cell)), g.dims - 1);
        for (int z = from.z; z <= to.z; ++z)
          for (int y = from.y; y <= to.y; ++y)
            for (int x = from.x; x <= to.x; ++x)
              add(g.index({x, y, z}), std::uint32_t(f));
      }
    };
    each([&](std::size_t c, std::uint32_t) { ++start[c + 1]; });
    for (std::size_t c = 0; c < cells; ++c)
      start[c + 1] += start[c];
    items.resize(start.back());
    std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
    each([&](std::size_t c, std::uint32_t f) { items[next[c]++] = f; });
  };
  fill(
      features.edges.size(),
      [&](std::size_t f, glm::dvec3& a, glm::dvec3& b) {
        a = glm::min(features.edges[f].a, features.edges[f].b);
        b = glm::max(features.edges[f].a, features.edges[f].b);
      },
      g.edge_start, g.edges);
  fill(
      features.corners.size(), [&](std::size_t f, glm::dvec3& a, glm::dvec3& b) { a = b = features.corners[f].p; },
      g.corner_start, g.corners);
  return g;
}

FaceAdjacency buildFaceAdjacency(const Topology& topology) {
  FaceAdjacency out;
  const std::size_t n = topology.initial_positions.size();
  const auto& tri = topology.triangles;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::size_t t = 0; t + 2 < tri.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[t + std::size_t(k)], b = tri[t + std::size_t((k + 1) % 3)];
      edges.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (const auto& [a, b] : edges) {
    out.edges.push_back(a);
    out.edges.push_back(b);
    out.longest_rest_edge =
        std::max(out.longest_rest_edge, glm::distance(topology.initial_positions[a], topology.initial_positions[b]));
  }
  // Per point, ascending: counted, then filled in ascending edge (triangle) order.
  auto csr = [n](std::size_t items, auto corners_of, std::vector<std::uint32_t>& start,
                 std::vector<std::uint32_t>& list) {
    start.assign(n + 1, 0);
    for (std::size_t e = 0; e < items; ++e)
      corners_of(e, [&](std::uint32_t p) { ++start[p + 1]; });
    for (std::size_t p = 0; p < n; ++p)
      start[p + 1] += start[p];
    list.resize(start.back());
    std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
    for (std::size_t e = 0; e < items; ++e)
      corners_of(e, [&](std::uint32_t p) { list[next[p]++] = std::uint32_t(e); });
  };
  csr(
      edges.size(),
      [&](std::size_t e, auto add) {
        add(edges[e].first);
        add(edges[e].second);
      },
      out.edge_start, out.point_edges);
  csr(
      tri.size() / 3,
      [&](std::size_t t, auto add) {
        for (int k = 0; k < 3; ++k)
          add(tri[3 * t + std::size_t(k)]);
      },
      out.triangle_start, out.point_triangles);
  return out;
}

namespace {

bool againstAPlane(const Scene& scene, glm::dvec3 a, glm::dvec3 b, glm::dvec3 out) {
  constexpr double kOnPlane = 1e-3;  // m
  for (const PlaneSpec& p : scene.planes)
    if (std::abs(glm::dot(a - p.point, p.normal)) < kOnPlane && std::abs(glm::dot(b - p.point, p.normal)) < kOnPlane &&
        glm::dot(out, p.normal) < 0.0)
      return true;
  return false;
}

}  // namespace

MeshFeatures contactFeatures(const Scene& scene, const MeshSpec& mesh) {
  const MeshFeatures all = findFeatures(*mesh.mesh);
  MeshFeatures kept;
  for (const FeatureEdge& e : all.edges)
    if (!againstAPlane(scene, e.a, e.b, e.normal_a + e.normal_b)) kept.edges.push_back(e);
  for (const FeatureCorner& c : all.corners)
    if (!againstAPlane(scene, c.p, c.p, c.normal)) kept.corners.push_back(c);
  return kept;
}

double featureReach(double thickness, const FaceAdjacency& faces) {
  return thickness + faces.longest_rest_edge;
}

}  // namespace drape
