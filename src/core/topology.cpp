#include "core/topology.hpp"

#include "core/cloth_mesh.hpp"
#include "core/hash.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace drape {

double verticalOffset(std::uint32_t index) {
  // Seeded by the index alone so that every run, and both solvers, start from the same positions.
  return (double(hashU32(index ^ 0x9e3779b9U)) / 4294967295.0 * 2.0 - 1.0) * 1e-3;
}

std::size_t Topology::springCount(SpringType t) const {
  return std::size_t(std::count_if(springs.begin(), springs.end(), [t](const Spring& s) { return s.type == t; }));
}

namespace {

// Direction d's springs on a W x H grid: one for each end (x, y) whose start (x - dx, y - dy) is on the grid
std::size_t gridSpringCount(int W, int H, int d) {
  return std::size_t(W - std::abs(kGridDirections[d][0])) * std::size_t(H - kGridDirections[d][1]);
}

void addSprings(Topology& topo, SpringType type, int dx, int dy) {
  // The spring from (x, y) to (x - dx, y - dy): "left" is dx > 0, "above" is dy > 0, upper-right dx < 0.
  for (int y = 0; y < topo.H; ++y)
    for (int x = 0; x < topo.W; ++x) {
      int ox = x - dx, oy = y - dy;
      if (ox < 0 || ox >= topo.W || oy < 0) continue;
      auto a = std::uint32_t(oy * topo.W + ox), b = std::uint32_t(y * topo.W + x);
      topo.springs.push_back({a, b, type, glm::distance(topo.initial_positions[a], topo.initial_positions[b])});
    }
}

// buildAdjacency's lists of a grid straight from its layout: a point's springs in ascending index are, direction by
// direction, the one that ends at it (from the point dx, dy before it) and then the one that starts at it (which
// addSprings numbered later, as it numbers by end point). Written point after point, where buildAdjacency scatters
// two entries a spring across the array: at 512 x 512, 3.1 million entries of 24 bytes, a quarter of a solver's set-up.
void buildGridAdjacency(Topology& topo) {
  const int W = topo.W, H = topo.H;
  std::uint32_t base[kGridDirectionCount];  // the index of direction d's first spring
  std::uint32_t springs = 0;
  for (int d = 0; d < kGridDirectionCount; ++d) {
    base[d] = springs;
    springs += std::uint32_t(gridSpringCount(W, H, d));
  }
  // The index addSprings gave the spring of direction d that ends at (x, y), a valid end
  const auto index = [&](int d, int x, int y) {
    const int dx = kGridDirections[d][0], dy = kGridDirections[d][1];
    return base[d] + std::uint32_t((y - dy) * (W - std::abs(dx)) + (x - std::max(0, dx)));
  };
  const auto add = [&](std::uint32_t other, std::uint32_t s) {
    const Spring& spring = topo.springs[s];
    topo.adjacency.push_back({other, s, spring.type, spring.rest});
  };
  topo.offsets.resize(std::size_t(W) * std::size_t(H) + 1);
  topo.adjacency.clear();
  topo.adjacency.reserve(2 * topo.springs.size());
  topo.offsets[0] = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      for (int d = 0; d < kGridDirectionCount; ++d) {
        const int dx = kGridDirections[d][0], dy = kGridDirections[d][1];
        if (x - dx >= 0 && x - dx < W && y - dy >= 0) add(std::uint32_t((y - dy) * W + x - dx), index(d, x, y));
        if (x + dx >= 0 && x + dx < W && y + dy < H)
          add(std::uint32_t((y + dy) * W + x + dx), index(d, x + dx, y + dy));
      }
      topo.offsets[std::size_t(y) * std::size_t(W) + std::size_t(x) + 1] = std::uint32_t(topo.adjacency.size());
    }
}

}  // namespace

void buildAdjacency(Topology& topo) {
  std::size_t n = topo.initial_positions.size();
  topo.offsets.assign(n + 1, 0);
  for (const Spring& s : topo.springs) {
    ++topo.offsets[s.a + 1];
    ++topo.offsets[s.b + 1];
  }
  for (std::size_t i = 0; i < n; ++i)
    topo.offsets[i + 1] += topo.offsets[i];
  topo.adjacency.resize(topo.offsets[n]);
  std::vector<std::uint32_t> fill(topo.offsets.begin(), topo.offsets.end() - 1);
  // Visiting springs in index order leaves every list in ascending spring index: the fixed summation
  // order that makes CPU and GPU force sums comparable.
  for (std::uint32_t s = 0; s < topo.springs.size(); ++s) {
    const Spring& sp = topo.springs[s];
    topo.adjacency[fill[sp.a]++] = {sp.b, s, sp.type, sp.rest};
    topo.adjacency[fill[sp.b]++] = {sp.a, s, sp.type, sp.rest};
  }
}

namespace {

// Pins by index and by box, for either generator.
void addPins(Topology& topo, const ClothSpec& cloth) {
  for (std::uint32_t i : cloth.pinned_vertices) {
    if (i >= topo.pinned.size())
      throw std::invalid_argument("cloth pin: vertex " + std::to_string(i) + " of a cloth of " +
                                  std::to_string(topo.pinned.size()) + " points");
    topo.pinned[i] = 1;
  }
  if (!cloth.has_pin_box) return;
  for (std::size_t i = 0; i < topo.initial_positions.size(); ++i) {
    const glm::dvec3& x = topo.initial_positions[i];
    if (glm::all(glm::greaterThanEqual(x, cloth.pin_box_min)) && glm::all(glm::lessThanEqual(x, cloth.pin_box_max)))
      topo.pinned[i] = 1;
  }
}

Topology buildMeshTopology(const ClothSpec& cloth) {
  const ClothMesh& mesh = *cloth.mesh;
  Topology topo;
  topo.initial_positions = mesh.positions;
  topo.uvs = mesh.uvs;
  topo.triangles = mesh.triangles;
  topo.faces = mesh.faces;
  topo.area = mesh.area;
  topo.normal_stencil = mesh.normal_stencil;
  topo.pinned.assign(mesh.positions.size(), 0);
  addPins(topo, cloth);
  topo.springs.reserve(mesh.springs.size());
  for (const MeshSpring& s : mesh.springs)
    topo.springs.push_back({s.a, s.b, s.type, glm::distance(mesh.positions[s.a], mesh.positions[s.b])});
  buildAdjacency(topo);
  return topo;
}

}  // namespace

// A scene file's cloth is validated when it is read (core/scene.cpp); a ClothSpec made or changed in code is checked
// here for what would index past the arrays (a pin off the grid) or divide by zero (a grid under 2 x 2).
Topology buildTopology(const ClothSpec& cloth) {
  if (cloth.mesh) return buildMeshTopology(cloth);
  if (cloth.num_width_points < 2 || cloth.num_height_points < 2)
    throw std::invalid_argument("cloth: a grid of " + std::to_string(cloth.num_width_points) + " x " +
                                std::to_string(cloth.num_height_points) + " points (at least 2 x 2)");
  for (glm::ivec2 p : cloth.pinned)
    if (p.x < 0 || p.y < 0 || p.x >= cloth.num_width_points || p.y >= cloth.num_height_points)
      throw std::invalid_argument("cloth pin: [" + std::to_string(p.x) + ", " + std::to_string(p.y) +
                                  "] is off the grid of " + std::to_string(cloth.num_width_points) + " x " +
                                  std::to_string(cloth.num_height_points) + " points");
  Topology topo;
  topo.W = cloth.num_width_points;
  topo.H = cloth.num_height_points;
  const int W = topo.W, H = topo.H;
  const double dx = cloth.width / (W - 1), dy = cloth.height / (H - 1);

  topo.initial_positions.resize(std::size_t(W) * H);
  topo.uvs.resize(std::size_t(W) * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      auto i = std::uint32_t(y * W + x);
      topo.initial_positions[i] = cloth.orientation == Orientation::Horizontal
                                      ? glm::dvec3(x * dx, 1.0, y * dy)
                                      : glm::dvec3(x * dx, y * dy, verticalOffset(i));
      topo.uvs[i] = glm::vec2(float(x) / float(W - 1), float(y) / float(H - 1));
    }

  topo.pinned.assign(std::size_t(W) * H, 0);
  for (glm::ivec2 p : cloth.pinned)
    topo.pinned[std::size_t(p.y) * W + p.x] = 1;
  addPins(topo, cloth);
  topo.area.assign(std::size_t(W) * H, cloth.width * cloth.height / double(W * H));
  topo.normal_stencil.resize(std::size_t(W) * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      auto at = [W](int px, int py) { return std::uint32_t(py * W + px); };
      topo.normal_stencil[std::size_t(at(x, y))] = {at(std::max(x - 1, 0), y), at(std::min(x + 1, W - 1), y),
                                                    at(x, std::max(y - 1, 0)), at(x, std::min(y + 1, H - 1))};
    }

  // Structural, then shearing, then bending (counts in docs/design.md section 2). Reserved up front: growing
  // a vector of 6 springs per point doubles its memory while it copies, which made the largest grid
  // take minutes and twice its final size.
  std::size_t springs = 0;
  for (int d = 0; d < kGridDirectionCount; ++d)
    springs += gridSpringCount(W, H, d);
  topo.springs.reserve(springs);
  for (int d = 0; d < kGridDirectionCount; ++d)
    addSprings(topo, gridDirectionType(d), kGridDirections[d][0], kGridDirections[d][1]);
  buildGridAdjacency(topo);

  // Two triangles per quad, wound so that a horizontal cloth faces +y.
  topo.triangles.reserve(std::size_t(W - 1) * (H - 1) * 6);
  topo.faces.reserve(std::size_t(W - 1) * (H - 1));
  for (int y = 0; y + 1 < H; ++y)
    for (int x = 0; x + 1 < W; ++x) {
      auto p00 = std::uint32_t(y * W + x), p10 = p00 + 1, p01 = p00 + std::uint32_t(W), p11 = p01 + 1;
      topo.triangles.insert(topo.triangles.end(), {p00, p01, p10, p10, p01, p11});
      topo.faces.push_back({p00, p01, p11, p10});
    }
  return topo;
}

}  // namespace drape
