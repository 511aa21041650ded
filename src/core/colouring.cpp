#include "core/colouring.hpp"

#include <bit>
#include <stdexcept>

namespace drape {

SpringColouring colourSprings(const Topology& topo) {
  // Colours in use at each point, as a bit mask: a point of a cloth has at most a dozen springs, so
  // 64 colours are far more than greedy colouring (at most 2 * degree - 1) can need.
  std::vector<std::uint64_t> used(std::size_t(topo.pointCount()), 0);
  std::vector<int> colour(topo.springs.size());
  int colours = 0;
  for (std::size_t s = 0; s < topo.springs.size(); ++s) {
    const Spring& sp = topo.springs[s];
    const std::uint64_t taken = used[sp.a] | used[sp.b];
    if (~taken == 0) throw std::runtime_error("colourSprings: a point has more than 64 spring colours");
    const int c = std::countr_one(taken);
    colour[s] = c;
    used[sp.a] |= std::uint64_t(1) << c;
    used[sp.b] |= std::uint64_t(1) << c;
    colours = std::max(colours, c + 1);
  }
  SpringColouring out;
  out.start.assign(std::size_t(colours) + 1, 0);
  for (int c : colour)
    ++out.start[std::size_t(c) + 1];
  for (int c = 0; c < colours; ++c)
    out.start[std::size_t(c) + 1] += out.start[std::size_t(c)];
  out.springs.resize(topo.springs.size());
  std::vector<std::uint32_t> fill(out.start.begin(), out.start.end() - 1);
  for (std::size_t s = 0; s < colour.size(); ++s)
    out.springs[fill[std::size_t(colour[s])]++] = std::uint32_t(s);
  return out;
}

PointColouring colourPoints(const Topology& topo) {
  const std::size_t n = std::size_t(topo.pointCount());
  std::vector<int> colour(n, -1);
  std::vector<std::size_t> seen_at;  // per colour: the last point whose neighbour had it (no clearing per point)
  int colours = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t e = topo.offsets[i]; e < topo.offsets[i + 1]; ++e)
      if (const int c = colour[topo.adjacency[e].other]; c >= 0) seen_at[std::size_t(c)] = i + 1;
    int c = 0;
    while (c < colours && seen_at[std::size_t(c)] == i + 1)
      ++c;
    if (c == colours) {
      ++colours;
      seen_at.push_back(0);
    }
    colour[i] = c;
  }
  PointColouring out;
  out.start.assign(std::size_t(colours) + 1, 0);
  for (int c : colour)
    ++out.start[std::size_t(c) + 1];
  for (int c = 0; c < colours; ++c)
    out.start[std::size_t(c) + 1] += out.start[std::size_t(c)];
  out.points.resize(n);
  std::vector<std::uint32_t> fill(out.start.begin(), out.start.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    out.points[fill[std::size_t(colour[i])]++] = std::uint32_t(i);
  return out;
}

}  // namespace drape
