#include "core/colouring.hpp"

#include <algorithm>
#include <bit>
#include <cstdlib>
#include <stdexcept>

namespace drape {

int gridDirection(const Topology& topo, const Spring& s) {
  const auto w = std::uint32_t(topo.W);
  const int dx = int(s.b % w) - int(s.a % w), dy = int(s.b / w) - int(s.a / w);
  for (int d = 0; d < kGridDirectionCount; ++d)
    if (kGridDirections[d][0] == dx && kGridDirections[d][1] == dy) return d;
  throw std::runtime_error("gridDirection: a spring in no grid direction");
}

namespace {

// Groups item indices by colour: ascending within a colour, colours in order.
void groupByColour(const std::vector<int>& colour, int colours, std::vector<std::uint32_t>& start,
                   std::vector<std::uint32_t>& items) {
  start.assign(std::size_t(colours) + 1, 0);
  for (int c : colour)
    ++start[std::size_t(c) + 1];
  for (int c = 0; c < colours; ++c)
    start[std::size_t(c) + 1] += start[std::size_t(c)];
  items.resize(colour.size());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < colour.size(); ++i)
    items[fill[std::size_t(colour[i])]++] = std::uint32_t(i);
}

// A grid's springs run in six directions (topology.cpp, addSprings), and along one direction the springs
// through a point alternate in the parity of where they start: colour 2 * direction + parity. In the
// interior this is what greedy colouring in spring order gives; at the border greedy would reuse a free
// low colour for a spring of another direction, which lets a Gauss-Seidel pass carry a change 17 points
// instead of 10 (gridColourReach), and the tiled stretch kernel copies that many points around a block.
SpringColouring colourGridSprings(const Topology& topo) {
  const auto w = std::uint32_t(topo.W);
  std::vector<int> colour(topo.springs.size());
  for (std::size_t s = 0; s < topo.springs.size(); ++s) {
    const Spring& sp = topo.springs[s];
    const int direction = gridDirection(topo, sp);
    const int ax = int(sp.a % w), ay = int(sp.a / w);
    const int along = kGridDirections[direction][1] == 0 ? ax : ay;  // the coordinate that advances along it
    colour[s] = 2 * direction + (direction >= 4 ? along / 2 : along) % 2;
  }
  SpringColouring out;
  groupByColour(colour, 12, out.start, out.springs);
  return out;
}

}  // namespace

SpringColouring colourSprings(const Topology& topo) {
  if (topo.W > 0) return colourGridSprings(topo);
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
  groupByColour(colour, colours, out.start, out.springs);
  return out;
}

int gridColourReach(const Topology& topo, const SpringColouring& colouring, int passes, unsigned type_mask) {
  if (topo.W <= 0) throw std::invalid_argument("gridColourReach: not a grid cloth");
  const auto w = std::uint32_t(topo.W);
  // Per point, the box (relative to it) holding every point its value depends on. Boxes, not distances:
  // a colour of vertical springs carries nothing sideways, so x and y reaches grow separately.
  struct Box {
    int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  };
  std::vector<Box> box(std::size_t(topo.pointCount()));
  const auto widened = [](Box mine, const Box& theirs, int dx, int dy) {
    mine.x0 = std::min(mine.x0, theirs.x0 + dx);
    mine.x1 = std::max(mine.x1, theirs.x1 + dx);
    mine.y0 = std::min(mine.y0, theirs.y0 + dy);
    mine.y1 = std::max(mine.y1, theirs.y1 + dy);
    return mine;
  };
  for (int pass = 0; pass < passes; ++pass)
    for (int c = 0; c < colouring.colourCount(); ++c)
      // Springs of a colour share no point, so updating in place is updating all at once.
      for (std::uint32_t k = colouring.start[std::size_t(c)]; k < colouring.start[std::size_t(c) + 1]; ++k) {
        const Spring& s = topo.springs[colouring.springs[k]];
        if (((type_mask >> unsigned(s.type)) & 1U) == 0) continue;
        const int dx = int(s.b % w) - int(s.a % w), dy = int(s.b / w) - int(s.a / w);
        const Box a = box[s.a], b = box[s.b];
        box[s.a] = widened(a, b, dx, dy);
        box[s.b] = widened(b, a, -dx, -dy);
      }
  int reach = 0;
  for (const Box& b : box)
    reach = std::max({reach, -b.x0, b.x1, -b.y0, b.y1});
  return reach;
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
  groupByColour(colour, colours, out.start, out.points);
  return out;
}

}  // namespace drape
