#include "core/mesh_obstacle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

namespace drape {
namespace {

// Closest point on triangle abc to p, by the region p projects into (vertex, edge or face).
glm::dvec3 closestOnTriangle(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Where the vertical line through (x, z) meets the triangle, if it does, and whether the triangle faces up
// there (+1) or down (-1). The caller shifts (x, z) off the
// sample lattice by an irrational fraction of a cell, so that no line runs exactly through an edge or a
// vertex and every crossing is counted once.
bool verticalCrossing(double x, double z, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, double& y, int& facing) {
  const double e0 = (b.x - a.x) * (z - a.z) - (b.z - a.z) * (x - a.x);
  const double e1 = (c.x - b.x) * (z - b.z) - (c.z - b.z) * (x - b.x);
  const double e2 = (a.x - c.x) * (z - c.z) - (a.z - c.z) * (x - c.x);
  if (!((e0 > 0 && e1 > 0 && e2 > 0) || (e0 < 0 && e1 < 0 && e2 < 0))) return false;
  const double sum = e0 + e1 + e2;
  // e1, e2, e0 are twice the areas opposite a, b, c.
  y = (e1 * a.y + e2 * b.y + e0 * c.y) / sum;
  facing = glm::cross(b - a, c - a).y > 0 ? 1 : -1;
  return true;
}

glm::dvec2 columnShift(double cell) {
  return cell * glm::dvec2(0.5773502691896258e-3, 0.3183098861837907e-3);
}

}  // namespace

MeshObstacle buildMeshObstacle(const PolygonMesh& mesh, glm::dvec3 offset, double scale) {
  MeshObstacle out;
  out.positions.reserve(mesh.positions.size());
  for (const glm::dvec3& p : mesh.positions)
    out.positions.push_back(p * scale + offset);
  checkFloatRange(out.positions);
  const auto& x = out.positions;
  // Directed edges: a closed, consistently wound surface has each edge once in each direction.
  std::unordered_map<std::uint64_t, int> edges;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    if (face.size() < 3)
      throw MeshError("face " + std::to_string(f) + " has " + std::to_string(face.size()) + " corners (at least 3)");
    for (std::size_t k = 1; k + 1 < face.size(); ++k) {
      const std::uint32_t a = face[0], b = face[k], c = face[k + 1];
      const double longest =
          std::max({glm::distance(x[a], x[b]), glm::distance(x[b], x[c]), glm::distance(x[c], x[a])});
      if (!(glm::length(glm::cross(x[b] - x[a], x[c] - x[a])) > 1e-6 * longest * longest))
        throw MeshError("face " + std::to_string(f) + " is degenerate: the triangle of vertices " + std::to_string(a) +
                        ", " + std::to_string(b) + ", " + std::to_string(c) + " has zero area");
      out.triangles.insert(out.triangles.end(), {a, b, c});
    }
    for (std::size_t k = 0; k < face.size(); ++k) {
      const std::uint32_t a = face[k], b = face[(k + 1) % face.size()];
      ++edges[(std::uint64_t(a) << 32) | b];
    }
  }
  for (const auto& [key, count] : edges) {
    const auto a = std::uint32_t(key >> 32), b = std::uint32_t(key & 0xffffffffu);
    const auto back = edges.find((std::uint64_t(b) << 32) | a);
    const int reverse = back == edges.end() ? 0 : back->second;
    if (count != 1 || reverse != 1)
      throw MeshError("not a closed, consistently wound surface: the edge from vertex " + std::to_string(a) + " to " +
                      std::to_string(b) + " is in " + std::to_string(count) + " faces that way and " +
                      std::to_string(reverse) + " the other way (an obstacle needs an inside: one each)");
  }
  // Wound inward (negative volume): turned around, so that facing up means leaving the inside.
  double volume = 0.0;
  for (std::size_t t = 0; t + 2 < out.triangles.size(); t += 3)
    volume += glm::dot(x[out.triangles[t]], glm::cross(x[out.triangles[t + 1]], x[out.triangles[t + 2]]));
  if (volume < 0.0)
    for (std::size_t t = 0; t + 2 < out.triangles.size(); t += 3)
      std::swap(out.triangles[t + 1], out.triangles[t + 2]);

  glm::dvec3 lo = x.front(), hi = x.front();
  for (const glm::dvec3& p : x) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  DistanceField& field = out.field;
  const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  field.cell = extent / kFieldResolution;
  field.band = kFieldBandCells * field.cell;
  const double pad = field.band + 2.0 * field.cell;
  field.origin = lo - pad;
  field.dims = glm::ivec3(glm::ceil((hi - lo + 2.0 * pad) / field.cell)) + 1;
  field.origin_f = glm::vec3(field.origin);
  field.inv_cell_f = float(1.0 / field.cell);

  // Unsigned distances, exact within the band of each triangle.
  const glm::ivec3 dims = field.dims;
  std::vector<double> dist(std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(dims.z),
                           std::numeric_limits<double>::infinity());
  auto sample = [&](int i, int j, int k) { return field.origin + field.cell * glm::dvec3(i, j, k); };
  const std::size_t triangle_count = out.triangles.size() / 3;
  for (std::size_t t = 0; t < triangle_count; ++t) {
    const glm::dvec3 a = x[out.triangles[3 * t]], b = x[out.triangles[3 * t + 1]], c = x[out.triangles[3 * t + 2]];
    const glm::dvec3 tlo = glm::min(a, glm::min(b, c)) - field.band, thi = glm::max(a, glm::max(b, c)) + field.band;
    const glm::ivec3 from = glm::max(glm::ivec3(glm::ceil((tlo - field.origin) / field.cell)), glm::ivec3(0));
    const glm::ivec3 to = glm::min(glm::ivec3(glm::floor((thi - field.origin) / field.cell)), dims - 1);
    for (int k = from.z; k <= to.z; ++k)
      for (int j = from.y; j <= to.y; ++j)
        for (int i = from.x; i <= to.x; ++i) {
          const glm::dvec3 p = sample(i, j, k);
          double& d = dist[field.index(i, j, k)];
          d = std::min(d, glm::distance(p, closestOnTriangle(p, a, b, c)));
        }
  }

  // Inside or outside: the parity of the surface crossings above each sample, one vertical line per column.
  std::vector<std::vector<std::uint32_t>> columns(std::size_t(dims.x) * std::size_t(dims.z));
  for (std::size_t t = 0; t < triangle_count; ++t) {
    const glm::dvec3 a = x[out.triangles[3 * t]], b = x[out.triangles[3 * t + 1]], c = x[out.triangles[3 * t + 2]];
    const glm::dvec3 tlo = glm::min(a, glm::min(b, c)), thi = glm::max(a, glm::max(b, c));
    const int i0 = std::max(int(std::floor((tlo.x - field.origin.x) / field.cell)), 0);
    const int i1 = std::min(int(std::ceil((thi.x - field.origin.x) / field.cell)), dims.x - 1);
    const int k0 = std::max(int(std::floor((tlo.z - field.origin.z) / field.cell)), 0);
    const int k1 = std::min(int(std::ceil((thi.z - field.origin.z) / field.cell)), dims.z - 1);
    for (int k = k0; k <= k1; ++k)
      for (int i = i0; i <= i1; ++i)
        columns[std::size_t(k) * std::size_t(dims.x) + std::size_t(i)].push_back(std::uint32_t(t));
  }
  field.samples.resize(dist.size());
  const glm::dvec2 shift = columnShift(field.cell);
  std::vector<std::pair<double, int>> crossings;
  for (int k = 0; k < dims.z; ++k)
    for (int i = 0; i < dims.x; ++i) {
      const glm::dvec3 base = sample(i, 0, k);
      crossings.clear();
      for (std::uint32_t t : columns[std::size_t(k) * std::size_t(dims.x) + std::size_t(i)]) {
        double y;
        int facing;
        if (verticalCrossing(base.x + shift.x, base.z + shift.y, x[out.triangles[3 * t]], x[out.triangles[3 * t + 1]],
                             x[out.triangles[3 * t + 2]], y, facing))
          crossings.emplace_back(y, facing);
      }
      std::sort(crossings.begin(), crossings.end());
      // Winding number: how many of the (possibly overlapping) closed parts hold the sample, counted from
      // the surfaces above it: one facing up is left through, one facing down entered.
      int winding = 0;
      for (const auto& c : crossings)
        winding += c.second;
      std::size_t below = 0;
      for (int j = 0; j < dims.y; ++j) {
        const double y = base.y + field.cell * j;
        for (; below < crossings.size() && crossings[below].first <= y; ++below)
          winding -= crossings[below].second;
        const bool inside = winding > 0;
        const std::size_t s = field.index(i, j, k);
        const double d = std::min(dist[s], field.band);
        field.samples[s] = float(inside ? -d : d);
      }
    }
  return out;
}

double unsignedDistance(const MeshObstacle& mesh, glm::dvec3 p) {
  double best = std::numeric_limits<double>::infinity();
  const auto& x = mesh.positions;
  for (std::size_t t = 0; t + 2 < mesh.triangles.size(); t += 3)
    best = std::min(best, glm::distance(p, closestOnTriangle(p, x[mesh.triangles[t]], x[mesh.triangles[t + 1]],
                                                             x[mesh.triangles[t + 2]])));
  return best;
}

std::optional<double> fieldDistance(const DistanceField& field, glm::dvec3 p) {
  const glm::dvec3 g = (p - field.origin) / field.cell;
  // Written so that NaN fails too.
  if (!(g.x >= 0 && g.y >= 0 && g.z >= 0 && g.x <= field.dims.x - 1 && g.y <= field.dims.y - 1 &&
        g.z <= field.dims.z - 1))
    return std::nullopt;
  // The last sample of an axis takes the cell below it, at t = 1.
  const glm::ivec3 i = glm::min(glm::ivec3(glm::floor(g)), field.dims - 2);
  const glm::dvec3 t = g - glm::dvec3(i);
  auto s = [&](int dx, int dy, int dz) { return double(field.samples[field.index(i.x + dx, i.y + dy, i.z + dz)]); };
  const double x00 = glm::mix(s(0, 0, 0), s(1, 0, 0), t.x), x10 = glm::mix(s(0, 1, 0), s(1, 1, 0), t.x);
  const double x01 = glm::mix(s(0, 0, 1), s(1, 0, 1), t.x), x11 = glm::mix(s(0, 1, 1), s(1, 1, 1), t.x);
  return glm::mix(glm::mix(x00, x10, t.y), glm::mix(x01, x11, t.y), t.z);
}

double triangleDistance(const MeshObstacle& mesh, std::size_t t, glm::dvec3 p) {
  const auto& x = mesh.positions;
  const auto& tri = mesh.triangles;
  return glm::distance(p, closestOnTriangle(p, x[tri[3 * t]], x[tri[3 * t + 1]], x[tri[3 * t + 2]]));
}

bool insideMesh(const MeshObstacle& mesh, glm::dvec3 p) {
  const glm::dvec2 shift = columnShift(mesh.field.cell);
  const auto& x = mesh.positions;
  int winding = 0;
  for (std::size_t t = 0; t + 2 < mesh.triangles.size(); t += 3) {
    double y;
    int facing;
    if (verticalCrossing(p.x + shift.x, p.z + shift.y, x[mesh.triangles[t]], x[mesh.triangles[t + 1]],
                         x[mesh.triangles[t + 2]], y, facing) &&
        y > p.y)
      winding += facing;
  }
  return winding > 0;
}

}  // namespace drape
