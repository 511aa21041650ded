#include "core/tethers.hpp"

#include <algorithm>
#include <array>
#include <queue>
#include <tuple>
#include <utility>

namespace drape {

namespace {

// Each point's `slots` nearest pins along the structural and shearing springs, and the length of that
// path: a Dijkstra search from all pins at once in which a point is settled once per pin, nearest pins
// first, and stops growing once it has all its slots, which bounds the work by slots x springs. Returns
// how many pins each point reached.
std::vector<std::uint8_t> searchNearestPins(const Topology& topo, const std::vector<std::uint32_t>& pins,
                                            Tethers& out) {
  const std::size_t slots = std::size_t(out.slots);
  std::vector<std::uint8_t> settled(std::size_t(topo.pointCount()), 0);
  // (distance, pin, point): ties go to the lower pin, then the lower point, so the anchors do not depend
  // on the queue's implementation.
  using Entry = std::tuple<double, std::uint32_t, std::uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (std::uint32_t p : pins)
    queue.emplace(0.0, p, p);
  const auto hasAnchor = [&](std::uint32_t point, std::uint32_t pin) {
    const std::uint32_t* first = &out.anchor[point * slots];
    return std::find(first, first + settled[point], pin) != first + settled[point];
  };
  while (!queue.empty()) {
    const auto [distance, pin, point] = queue.top();
    queue.pop();
    if (settled[point] == slots || hasAnchor(point, pin)) continue;
    out.anchor[point * slots + settled[point]] = pin;
    out.rest[point * slots + settled[point]] = distance;
    ++settled[point];
    // Along the sides and diagonals only: a bending spring's straight rest length cuts across a fold, and
    // a path over the surface is what the cloth can unfold to.
    for (std::uint32_t e = topo.offsets[point]; e < topo.offsets[point + 1]; ++e) {
      const Neighbor& nb = topo.adjacency[e];
      if (nb.type == SpringType::Bending || settled[nb.other] == slots || hasAnchor(nb.other, pin)) continue;
      queue.emplace(distance + nb.rest, pin, nb.other);
    }
  }
  return settled;
}

}  // namespace

Tethers buildTethers(const Topology& topo) {
  Tethers out;
  const std::size_t n = std::size_t(topo.pointCount());
  std::vector<std::uint32_t> pins;
  for (std::size_t i = 0; i < n; ++i)
    if (topo.pinned[i]) pins.push_back(std::uint32_t(i));
  out.slots = std::min(kMaxTethers, int(pins.size()));
  if (out.slots == 0) return out;
  const std::size_t slots = std::size_t(out.slots);
  out.anchor.assign(n * slots, kNoAnchor);
  out.rest.assign(n * slots, 0.0);
  const bool grid = topo.W > 0;
  std::vector<std::uint8_t> settled;
  if (grid && pins.size() <= slots) {
    // Every point is tied to every pin (a grid is connected), at the straight distances below: no search,
    // which at 1024 x 1024 points takes seconds.
    for (std::size_t i = 0; i < n; ++i)
      std::copy(pins.begin(), pins.end(), &out.anchor[i * slots]);
    settled.assign(n, std::uint8_t(slots));
  } else {
    settled = searchNearestPins(topo, pins, out);
  }
  for (std::size_t i = 0; i < n; ++i) {
    // A pin holds itself; its own slot (distance 0) and any others are not tethers.
    if (topo.pinned[i]) {
      std::fill_n(&out.anchor[i * slots], slots, kNoAnchor);
      std::fill_n(&out.rest[i * slots], slots, 0.0);
      continue;
    }
    const std::size_t used = settled[i];
    // A grid's rest shape is flat and convex: the straight line between two points stays on the cloth.
    if (grid)
      for (std::size_t s = 0; s < used; ++s)
        out.rest[i * slots + s] =
            glm::distance(topo.initial_positions[i], topo.initial_positions[out.anchor[i * slots + s]]);
    // Nearest first by rest distance (then by index): the order the pass applies them in.
    std::array<std::pair<double, std::uint32_t>, kMaxTethers> order;
    for (std::size_t s = 0; s < used; ++s)
      order[s] = {out.rest[i * slots + s], out.anchor[i * slots + s]};
    std::sort(order.begin(), order.begin() + std::ptrdiff_t(used));
    for (std::size_t s = 0; s < used; ++s)
      std::tie(out.rest[i * slots + s], out.anchor[i * slots + s]) = order[s];
  }
  return out;
}

}  // namespace drape
