#include "core/tethers.hpp"

#include <algorithm>
#include <queue>
#include <tuple>

namespace drape {

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
  std::vector<std::uint8_t> settled(n, 0);  // pins settled per point so far

  // (distance, pin, point): ties go to the lower pin, then the lower point, so the anchors do not depend
  // on the queue's implementation. A point is settled once per pin, nearest pins first; the search stops
  // growing from a point once it has all its slots, which bounds the work by slots x springs.
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
  for (std::size_t i = 0; i < n; ++i) {
    // A pin holds itself; its own slot (distance 0) and any others are not tethers.
    if (topo.pinned[i]) {
      std::fill_n(&out.anchor[i * slots], slots, kNoAnchor);
      std::fill_n(&out.rest[i * slots], slots, 0.0);
      continue;
    }
    if (topo.W == 0) continue;
    // A grid's rest shape is flat and convex: the straight line between two points stays on the cloth.
    for (std::size_t s = 0; s < slots; ++s)
      if (out.anchor[i * slots + s] != kNoAnchor)
        out.rest[i * slots + s] =
            glm::distance(topo.initial_positions[i], topo.initial_positions[out.anchor[i * slots + s]]);
  }
  return out;
}

}  // namespace drape
