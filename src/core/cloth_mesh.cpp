#include "core/cloth_mesh.hpp"

#include <algorithm>
#include <unordered_map>

namespace drape {
namespace {

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) {
  return a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a;
}

// A triangle whose height is below this fraction of its longest side has no area the float solvers can
// see (float keeps 24 bits): its mass share and its normal would be noise.
constexpr double kDegenerateRatio = 1e-6;

std::string vertexText(std::uint32_t v) {
  return "vertex " + std::to_string(v);
}

class SpringSet {
 public:
  explicit SpringSet(std::vector<MeshSpring>& out) : out_(out) {}
  // One spring per pair of vertices: the first type to claim a pair keeps it.
  void add(std::uint32_t a, std::uint32_t b, SpringType type) {
    if (seen_.emplace(edgeKey(a, b), 0).second) out_.push_back({std::min(a, b), std::max(a, b), type});
  }

 private:
  std::vector<MeshSpring>& out_;
  std::unordered_map<std::uint64_t, int> seen_;
};

std::vector<glm::vec2> projectedUvs(const std::vector<glm::dvec3>& x) {
  glm::dvec3 lo = x.front(), hi = x.front();
  for (const glm::dvec3& p : x) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::dvec3 extent = hi - lo;
  int axes[3] = {0, 1, 2};
  std::stable_sort(axes, axes + 3, [&](int a, int b) { return extent[a] > extent[b]; });
  std::vector<glm::vec2> uvs;
  uvs.reserve(x.size());
  for (const glm::dvec3& p : x) {
    auto along = [&](int axis) { return extent[axis] > 0 ? float((p[axis] - lo[axis]) / extent[axis]) : 0.0f; };
    uvs.emplace_back(along(axes[0]), along(axes[1]));
  }
  return uvs;
}

}  // namespace

ClothMesh buildClothMesh(const PolygonMesh& mesh) {
  ClothMesh out;
  checkFloatRange(mesh.positions);
  out.positions = mesh.positions;
  const std::size_t n = mesh.positions.size();
  const auto& x = out.positions;

  std::vector<char> used(n, 0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    const std::string name = "face " + std::to_string(f);
    if (face.size() < 3) throw MeshError(name + " has " + std::to_string(face.size()) + " corners (at least 3)");
    for (std::size_t k = 0; k < face.size(); ++k) {
      used[face[k]] = 1;
      for (std::size_t j = 0; j < k; ++j)
        if (face[j] == face[k]) throw MeshError(name + " is degenerate: " + vertexText(face[k]) + " appears twice");
    }
    if (face.size() == 4) {
      ++out.quads;
      out.faces.push_back({face[0], face[1], face[2], face[3]});
    }
    for (std::size_t k = 1; k + 1 < face.size(); ++k) {
      const std::uint32_t a = face[0], b = face[k], c = face[k + 1];
      const double longest =
          std::max({glm::distance(x[a], x[b]), glm::distance(x[b], x[c]), glm::distance(x[c], x[a])});
      const double twice_area = glm::length(glm::cross(x[b] - x[a], x[c] - x[a]));
      if (!(twice_area > kDegenerateRatio * longest * longest))
        throw MeshError(name + " is degenerate: the triangle of vertices " + std::to_string(a) + ", " +
                        std::to_string(b) + ", " + std::to_string(c) + " has zero area");
      out.triangles.insert(out.triangles.end(), {a, b, c});
      if (face.size() != 4) out.faces.push_back({a, b, c, kNoCorner});
    }
  }
  for (std::size_t v = 0; v < n; ++v)
    if (!used[v])
      throw MeshError(vertexText(std::uint32_t(v)) + " is in no face (a cloth point needs area for its mass)");

  // Every triangle edge, with the vertex opposite it in each triangle that has it.
  struct EdgeUse {
    std::uint32_t opposite[2];
    int count = 0;
  };
  std::unordered_map<std::uint64_t, EdgeUse> edges;
  std::vector<std::uint64_t> edge_order;  // first appearance, so the bending springs come in a fixed order
  const std::size_t triangle_count = out.triangles.size() / 3;
  for (std::size_t t = 0; t < triangle_count; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = out.triangles[3 * t + std::size_t(k)], b = out.triangles[3 * t + std::size_t(k + 1) % 3];
      const std::uint32_t c = out.triangles[3 * t + std::size_t(k + 2) % 3];
      auto [it, added] = edges.try_emplace(edgeKey(a, b));
      if (added) edge_order.push_back(it->first);
      EdgeUse& use = it->second;
      if (use.count == 2)
        throw MeshError("the edge between vertices " + std::to_string(std::min(a, b)) + " and " +
                        std::to_string(std::max(a, b)) + " is shared by more than two triangles (non-manifold)");
      use.opposite[use.count++] = c;
    }

  out.area.assign(n, 0.0);
  for (std::size_t t = 0; t < triangle_count; ++t) {
    const std::uint32_t* c = &out.triangles[3 * t];
    const double third = glm::length(glm::cross(x[c[1]] - x[c[0]], x[c[2]] - x[c[0]])) / 6.0;
    for (int k = 0; k < 3; ++k)
      out.area[c[k]] += third;
  }
  SpringSet springs(out.springs);
  // Structural: the sides of every face (not the diagonals that split quads and larger faces).
  for (const auto& face : mesh.faces)
    for (std::size_t k = 0; k < face.size(); ++k)
      springs.add(face[k], face[(k + 1) % face.size()], SpringType::Structural);
  // Shearing: both diagonals of each quad. A triangle holds its shape with its three sides alone.
  for (const auto& face : mesh.faces)
    if (face.size() == 4) {
      springs.add(face[0], face[2], SpringType::Shearing);
      springs.add(face[1], face[3], SpringType::Shearing);
    }
  // Bending: across every edge two triangles share, between the vertices opposite it.
  for (std::uint64_t key : edge_order) {
    const EdgeUse& use = edges[key];
    if (use.count == 2) springs.add(use.opposite[0], use.opposite[1], SpringType::Bending);
  }

  // The wind's normal stencil: among the vertex and its neighbours, the farthest pair spans one direction and
  // the pair whose span is most across it the other, which is the grid's left/right, down/up on a grid.
  std::vector<std::vector<std::uint32_t>> around(n);
  for (std::uint64_t key : edge_order) {
    const auto a = std::uint32_t(key >> 32), b = std::uint32_t(key & 0xffffffffu);
    around[a].push_back(b);
    around[b].push_back(a);
  }
  out.normal_stencil.resize(n);
  for (std::size_t v = 0; v < n; ++v) {
    std::vector<std::uint32_t> c = around[v];
    c.push_back(std::uint32_t(v));
    std::sort(c.begin(), c.end());
    std::array<std::uint32_t, 4> best{c[0], c[1], c[0], c[1]};
    double span = -1.0;
    for (std::size_t i = 0; i < c.size(); ++i)
      for (std::size_t j = i + 1; j < c.size(); ++j)
        if (double d = glm::distance(x[c[i]], x[c[j]]); d > span) {
          span = d;
          best[0] = c[i];
          best[1] = c[j];
        }
    const glm::dvec3 along = x[best[1]] - x[best[0]];
    double across = -1.0;
    for (std::size_t i = 0; i < c.size(); ++i)
      for (std::size_t j = i + 1; j < c.size(); ++j)
        if (double d = glm::length(glm::cross(along, x[c[j]] - x[c[i]])); d > across) {
          across = d;
          best[2] = c[i];
          best[3] = c[j];
        }
    out.normal_stencil[v] = best;
  }

  out.uvs_from_file = !mesh.uvs.empty();
  out.uvs = out.uvs_from_file ? mesh.uvs : projectedUvs(x);
  return out;
}

}  // namespace drape
