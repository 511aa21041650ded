#include "cpu/grid_path.hpp"
#include "core/health.hpp"

#include "core/colouring.hpp"
#include "cpu/parallel.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdint>
#include <limits>

namespace drape {

namespace {

constexpr SpringType kDirectionType[6] = {SpringType::Structural, SpringType::Structural, SpringType::Shearing,
                                          SpringType::Shearing,   SpringType::Bending,    SpringType::Bending};

}  // namespace

GridPath::GridPath(const Topology& topo, const std::vector<float>& rest, GridIsa isa)
    : shape_(GridShape::of(topo.W, topo.H)), kernels_(&gridKernels(isa)) {
  for (PaddedFloats* a : {&x_, &y_, &z_, &vx_, &vy_, &vz_, &pinned_, &mass_, &inv_mass_, &rx_, &ry_, &rz_})
    a->assign(shape_.size, 0.0f);
  for (PaddedFloats& r : rest_)
    r.assign(shape_.size, 0.0f);
  signed_rows_.assign(std::size_t(shape_.H), 1);
  padded_.resize(topo.initial_positions.size());
  for (std::size_t i = 0; i < padded_.size(); ++i)
    padded_[i] = std::uint32_t(shape_.at(int(i % topo.W), int(i / topo.W)));
  const auto w = std::uint32_t(topo.W);
  for (std::size_t s = 0; s < topo.springs.size(); ++s) {
    const Spring& sp = topo.springs[s];
    rest_[gridDirection(topo, sp)][std::size_t(shape_.at(int(sp.a % w), int(sp.a / w)))] = rest[s];
  }
  for (std::size_t i = 0; i < topo.initial_positions.size(); ++i) {
    const glm::vec3 r(topo.initial_positions[i]);
    const auto k = std::size_t(shape_.at(int(i % w), int(i / w)));
    rx_[k] = r.x;
    ry_[k] = r.y;
    rz_[k] = r.z;
  }
  const float all_bits = std::bit_cast<float>(std::numeric_limits<std::uint32_t>::max());
  for (std::size_t i = 0; i < topo.pinned.size(); ++i)
    if (topo.pinned[i]) pinned_[std::size_t(shape_.at(int(i % w), int(i / w)))] = all_bits;
}

void GridPath::setMasses(const std::vector<float>& mass, const std::vector<float>& inv_mass) {
  const auto w = std::size_t(shape_.W);
  for (std::size_t i = 0; i < mass.size(); ++i) {
    const auto k = std::size_t(shape_.at(int(i % w), int(i / w)));
    mass_[k] = mass[i];
    inv_mass_[k] = inv_mass[i];
  }
}

GridSprings GridPath::springs(const float k[3], const bool enabled[3]) const {
  GridSprings s;
  for (int d = 0; d < 6; ++d) {
    const int t = int(kDirectionType[d]);
    s.rest[d] = rest_[d].data();
    s.k[d] = k[t];
    s.enabled[d] = enabled[t];
  }
  return s;
}

void GridPath::forces(const std::vector<glm::vec3>& x, std::vector<glm::vec3>& f, glm::vec3 gravity, const float k[3],
                      const bool enabled[3], bool wait, bool loaded) {
  const GridKernels& kern = *kernels_;
  // Every row's neighbours must be in the arrays before any row's forces: a barrier between.
  if (!loaded)
    teamRange(0, shape_.H, [&](long long y0, long long y1) {
      kern.toSoa(shape_, &x.data()->x, x_.data(), y_.data(), z_.data(), int(y0), int(y1), nullptr);
    });
  const GridForceArgs args = forceArgs(f, gravity, k, enabled);
  teamPart(0, shape_.H, [&](long long y0, long long y1) { kern.forces(args, int(y0), int(y1)); });
  if (wait) teamBarrier();
}

GridForceArgs GridPath::forceArgs(std::vector<glm::vec3>& f, glm::vec3 gravity, const float k[3],
                                  const bool enabled[3]) const {
  return GridForceArgs{shape_,
                       x_.data(),
                       y_.data(),
                       z_.data(),
                       mass_.data(),
                       {gravity.x, gravity.y, gravity.z},
                       springs(k, enabled),
                       &f.data()->x};
}

GridIntegrateArgs GridPath::integrateArgs(std::vector<glm::vec3>* x_out, const std::vector<glm::vec3>& f, float dt2,
                                          float keep) {
  return GridIntegrateArgs{shape_,
                           x_.data(),
                           y_.data(),
                           z_.data(),
                           vx_.data(),
                           vy_.data(),
                           vz_.data(),
                           pinned_.data(),
                           inv_mass_.data(),
                           &f.data()->x,
                           x_out ? &x_out->data()->x : nullptr,
                           dt2,
                           keep,
                           signed_rows_.data()};
}

void GridPath::forcesAndIntegrate(std::vector<glm::vec3>* x_out, std::vector<glm::vec3>& f, glm::vec3 gravity,
                                  const float k[3], const bool enabled[3], float dt2, float keep) {
  const GridIntegrateArgs step = integrateArgs(x_out, f, dt2, keep);
  GridForceArgs args = forceArgs(f, gravity, k, enabled);
  args.integrate = &step;
  long long y0, y1;
  teamShare(0, shape_.H, y0, y1);
  // A thread's first and last two rows wait for the other threads' forces, which read them
  const bool first = !inTeam() || teamThread() == 0, last = !inTeam() || teamThread() == teamSize() - 1;
  args.integrate_from = int(first ? y0 : std::min(y0 + 2, y1));
  args.integrate_to = int(std::max<long long>(args.integrate_from, last ? y1 : y1 - 2));
  if (y0 < y1) kernels_->forces(args, int(y0), int(y1));
  if (first && last) return;
  teamBarrier();
  if (y0 < args.integrate_from) kernels_->integrateRows(step, int(y0), args.integrate_from);
  if (args.integrate_to < y1) kernels_->integrateRows(step, args.integrate_to, int(y1));
}

void GridPath::integrate(std::vector<glm::vec3>* x_out, const std::vector<glm::vec3>& f, float dt2, float keep) {
  const GridIntegrateArgs args = integrateArgs(x_out, f, dt2, keep);
  teamPart(0, shape_.H, [&](long long y0, long long y1) { kernels_->integrateRows(args, int(y0), int(y1)); });
}

void GridPath::loadPositions(const std::vector<glm::vec3>& x) {
  const GridKernels& kern = *kernels_;
  teamRange(0, shape_.H, [&](long long y0, long long y1) {
    kern.toSoa(shape_, &x.data()->x, x_.data(), y_.data(), z_.data(), int(y0), int(y1), nullptr);
  });
}

std::size_t GridPath::stencilPairs(const int* du, const int* dv, const std::uint8_t* mixed, int count, float range2,
                                   int y0, int y1, std::vector<std::uint32_t>& lower, std::vector<std::uint32_t>& upper,
                                   const GridStencilTiles* tiles) {
  // The forward half: each pair once, from its lower point
  const int half = count / 2, forward = count - half;
  GridStencilArgs args{shape_,     x_.data(), y_.data(), z_.data(),    rx_.data(), ry_.data(),
                       rz_.data(), du + half, dv + half, mixed + half, forward,    range2};
  int rows = kStencilRows;
  if (tiles) {
    args.edge = rows = tiles->edge;
    args.across = tiles->across;
    args.active = tiles->active;
    args.min2 = tiles->min2;
    args.record = tiles->record;
    args.shared_row = tiles->prepare(y0, y1);
    if (args.shared_row >= 0) args.shared_min2 = tiles->shared_min2;
  }
  // A few rows a call, with room for each of their points' every offset: the vectors stay the size of the pairs in
  // range and one call's room, not of the tests (20 offsets of 256 points a row at 256 x 256)
  std::size_t found = 0;
  for (int v = y0; v < y1; v += rows) {
    const int v1 = std::min(v + rows, y1);
    const std::size_t room = found + std::size_t(forward) * std::size_t(shape_.W) * std::size_t(v1 - v);
    if (lower.size() < room) {
      lower.resize(room);
      upper.resize(room);
    }
    args.lower = lower.data() + found;
    args.upper = upper.data() + found;
    found += std::size_t(kernels_->stencilPairs(args, v, v1));
  }
  return found;
}

void GridPath::limitStretch(std::vector<glm::vec3>& x, std::vector<glm::vec3>* v, float limit, int passes,
                            const bool enabled[3], bool wait, bool copy_out, bool loaded) {
  const float unit[3] = {1, 1, 1};
  GridStretchArgs args = colourArgs(v != nullptr, springs(unit, enabled));
  args.limit = limit;
  args.signed_rows = signed_rows_.data();  // made by copyIn or integrate, before the colours read it
  sweepColours(x, v, args, passes, kernels_->stretchColour, wait, copy_out, loaded);
}

void GridPath::collideAndCopyOut(std::vector<glm::vec3>& x, std::vector<glm::vec3>& v, const CollideArgs& objects,
                                 bool wait) {
  collide(objects);
  copyOut(x, &v, wait);
}

void GridPath::collide(const CollideArgs& objects) {
  const CollideRowsArgs args{objects,    shape_,     x_.data(),  y_.data(),     z_.data(),
                             vx_.data(), vy_.data(), vz_.data(), pinned_.data()};
  teamPart(0, shape_.H, [&](long long y0, long long y1) { kernels_->collideRows(args, int(y0), int(y1)); });
}

void GridPath::xpbd(std::vector<glm::vec3>& x, std::vector<glm::vec3>* v, const float alpha_tilde[3],
                    const bool enabled[3], int sweeps) {
  GridStretchArgs args = colourArgs(v != nullptr, springs(alpha_tilde, enabled));
  args.inv_mass = inv_mass_.data();
  // Several sweeps keep a multiplier a spring, from 0 each substep (Small Steps); one never reads it.
  if (sweeps > 1) {
    // One thread zeroes them (one barrier, not one a direction); every thread then points at them.
    teamSingle([&] {
      for (int d = 0; d < 6; ++d)
        if (args.springs.enabled[d]) lambda_[d].assign(shape_.size, 0.0f);
    });
    for (int d = 0; d < 6; ++d)
      if (args.springs.enabled[d]) args.lambda[d] = lambda_[d].data();
  }
  sweepColours(x, v, args, sweeps, kernels_->xpbdColour);
}

void GridPath::setVbdPoints(const std::vector<std::uint32_t>& points) {
  vbd_padded_.resize(points.size());
  vbd_column_.resize(points.size());
  vbd_row_.resize(points.size());
  const auto w = std::uint32_t(shape_.W);
  for (std::size_t e = 0; e < points.size(); ++e) {
    const int u = int(points[e] % w), row = int(points[e] / w);
    vbd_padded_[e] = std::int32_t(shape_.at(u, row));
    vbd_column_[e] = float(u);
    vbd_row_[e] = float(row);
  }
}

void GridPath::vbd(std::vector<glm::vec3>& x, std::vector<glm::vec3>* v, const float k[3], const bool enabled[3],
                   float dt2, int sweeps, const std::vector<std::uint32_t>& colour_start) {
  const GridKernels& kern = *kernels_;
  copyIn(x, v);
  if (sweeps > 1)
    teamSingle([&] {
      for (PaddedFloats* t : {&tx_, &ty_, &tz_})
        t->resize(shape_.size);
    });
  GridVbdArgs args{shape_,
                   x_.data(),
                   y_.data(),
                   z_.data(),
                   v ? vx_.data() : nullptr,
                   v ? vy_.data() : nullptr,
                   v ? vz_.data() : nullptr,
                   pinned_.data(),
                   inv_mass_.data(),
                   springs(k, enabled),
                   dt2,
                   vbd_padded_.data(),
                   vbd_column_.data(),
                   vbd_row_.data()};
  if (sweeps > 1) {
    args.target_x = tx_.data();
    args.target_y = ty_.data();
    args.target_z = tz_.data();
  }
  // A colour's points share no spring: split between the threads, a barrier after each colour.
  for (args.sweep = 0; args.sweep < sweeps; ++args.sweep)
    for (std::size_t c = 0; c + 1 < colour_start.size(); ++c)
      teamRange(colour_start[c], colour_start[c + 1],
                [&](long long lo, long long hi) { kern.vbdPoints(args, lo, hi); });
  copyOut(x, v);
}

void GridPath::setHealthLimits(const Topology& topo, const ClothSpec& cloth) {
  for (PaddedFloats& l : limit2_)
    l.clear();
  const auto w = std::uint32_t(topo.W);
  for (const Spring& sp : topo.springs) {
    if (!cloth.springEnabled(sp.type)) continue;
    PaddedFloats& l = limit2_[gridDirection(topo, sp)];
    if (l.empty()) l.assign(shape_.size, std::numeric_limits<float>::infinity());
    l[std::size_t(shape_.at(int(sp.a % w), int(sp.a / w)))] = quickLimit2(sp.rest, HealthLimits{});
  }
}

bool GridPath::healthy(float bound) const {
  GridHealthArgs args{shape_, x_.data(), y_.data(), z_.data(), vx_.data(), vy_.data(), vz_.data()};
  for (int d = 0; d < 6; ++d)
    args.limit2[d] = limit2_[d].empty() ? nullptr : limit2_[d].data();
  args.bound = bound;
  return kernels_->healthyRows(args, 0, shape_.H);
}

void GridPath::copyIn(const std::vector<glm::vec3>& x, const std::vector<glm::vec3>* v, bool wait) {
  const GridKernels& kern = *kernels_;
  teamPart(0, shape_.H, [&](long long y0, long long y1) {
    std::fill(signed_rows_.begin() + y0, signed_rows_.begin() + y1, std::uint8_t(0));
    kern.toSoa(shape_, &x.data()->x, x_.data(), y_.data(), z_.data(), int(y0), int(y1), signed_rows_.data());
    if (v) kern.toSoa(shape_, &v->data()->x, vx_.data(), vy_.data(), vz_.data(), int(y0), int(y1), signed_rows_.data());
  });
  if (wait) teamBarrier();
}

void GridPath::copyOut(std::vector<glm::vec3>& x, std::vector<glm::vec3>* v, bool wait) {
  const GridKernels& kern = *kernels_;
  teamPart(0, shape_.H, [&](long long y0, long long y1) {
    kern.fromSoa(shape_, x_.data(), y_.data(), z_.data(), &x.data()->x, int(y0), int(y1));
    if (v) kern.fromSoa(shape_, vx_.data(), vy_.data(), vz_.data(), &v->data()->x, int(y0), int(y1));
  });
  if (wait) teamBarrier();
}

GridStretchArgs GridPath::colourArgs(bool displacements, const GridSprings& s) {
  return GridStretchArgs{shape_,
                         x_.data(),
                         y_.data(),
                         z_.data(),
                         displacements ? vx_.data() : nullptr,
                         displacements ? vy_.data() : nullptr,
                         displacements ? vz_.data() : nullptr,
                         pinned_.data(),
                         s};
}

void GridPath::sweepColours(std::vector<glm::vec3>& x, std::vector<glm::vec3>* v, const GridStretchArgs& args,
                            int passes, ColourKernel colour, bool wait, bool copy_out, bool loaded) {
  // The colours in order (colourGridSprings: 2 * direction + parity); a colour's springs share no point and
  // every spring starts in the row its thread owns, so a colour is split by rows with a barrier after it. A
  // horizontal direction's springs lie in their rows, so its first colour needs no barrier after it, nor the copy
  // before it: each thread reads only the rows it wrote (3 of the 20 barriers a substep of CS184's files had).
  const auto horizontal = [](int d) { return kGridDirections[d][1] == 0; };
  int first = 0;
  while (first < 6 && !args.springs.enabled[first])
    ++first;
  long long y0, y1;
  const bool follow = followsColourTimes(), even = colourRows(follow, y0, y1);
  // Where the arrays hold the points already, the barrier the copy in would end with: the pass before may end
  // without one (CpuSolver::collide)
  const bool wait_in = passes <= 0 || first == 6 || !horizontal(first) || !even;
  if (!loaded)
    copyIn(x, v, wait_in);
  else if (wait_in)
    teamBarrier();
  // Where every thread's rows number kBand * 2 or more, a colour waits only for the threads next to it (colourBands)
  const bool bands = colourBands(follow);
  const int thread = teamThread(), team = teamSize();
  if (bands && colour_progress_.size() != unsigned(team)) {
    teamBarrier();  // every thread has read the size
    if (thread == 0) colour_progress_.resize(unsigned(team));
    teamBarrier();
  }
  const bool above = bands && thread > 0, below = bands && thread + 1 < team;
  std::uint32_t done = bands ? colour_progress_.count(unsigned(thread)) : 0;
  // Every thread's count is this one's at the start: each published the last sweep's colours before its barrier
  std::uint32_t seen_above = done, seen_below = done;
  int left = 0;  // colours, the last of which ends with the sweep's barrier
  for (int d = 0; d < 6; ++d)
    left += args.springs.enabled[d] ? 2 * std::max(passes, 0) : 0;
  const bool any = left > 0;
  using Clock = std::chrono::steady_clock;
  Clock::duration work{};
  const auto run = [&](long long from, long long to, int d, int parity) {
    if (from >= to) return;
    const auto start = follow ? Clock::now() : Clock::time_point();
    colour(args, d, parity, int(from), int(to));
    if (follow) work += Clock::now() - start;
  };
  for (int pass = 0; pass < passes; ++pass)
    for (int d = 0; d < 6; ++d) {
      if (!args.springs.enabled[d]) continue;
      for (int parity = 0; parity < 2; ++parity) {
        --left;
        if (!bands) {
          run(y0, y1, d, parity);
          if (left > 0 && (parity == 1 || !horizontal(d))) teamBarrier();
          continue;
        }
        run(above ? y0 + kBand : y0, below ? y1 - kBand : y1, d, parity);
        // A horizontal direction's second colour waits for nothing: its springs and its first colour's lie in their
        // rows, so its bands meet no row a neighbour wrote since the wait before that first colour
        const bool await = !(parity == 1 && horizontal(d));
        if (above && await) teamAwait(colour_progress_, thread - 1, done, seen_above);
        if (below && await) teamAwait(colour_progress_, thread + 1, done, seen_below);
        if (above) run(y0, y0 + kBand, d, parity);
        if (below) run(y1 - kBand, y1, d, parity);
        colour_progress_.publish(unsigned(thread), ++done);
      }
    }
  // Each thread's seconds before the last colour's barrier, which thread 0 reads after it; no thread reads the rows
  // again before the next sweep, several barriers on
  if (follow) colour_seconds_[std::size_t(thread)] = std::chrono::duration<double>(work).count();
  if (any) teamBarrier();
  if (follow && thread == 0 && passes > 0 && !colour_rows_fixed_)
    balanceShares(colour_rows_, colour_seconds_, colour_per_row_, 0.25, 2);
  if (copy_out) copyOut(x, v, wait || !even);
}

// Whether a team's colours wait for the neighbouring threads alone rather than for every thread: where every
// thread's rows number 2 kBand or more. A colour's springs start in the thread's rows and end at most kBand rows
// below (kGridDirections' dy), so its rows but the first and last kBand touch no row another thread's springs touch
// and can run at once; those bands wait until the neighbour's bands of the colour before are done. A thread then
// waits only where a neighbour is a whole colour behind, not for the slowest share at every colour: on CS184's
// pinned2 (a team of two, every substep) the barriers kept thread 0 waiting 8% of its run and thread 1 15%; with
// the bands thread 0 waits for none and thread 1 9% (the limit acts in the pins' rows, thread 0's, at every
// colour). The same springs in the same colours: the same bytes.
bool GridPath::colourBands(bool follow) const {
  if (!inTeam()) return false;
  const int team = teamSize();
  for (int t = 0; t < team; ++t) {
    const long long rows = follow ? colour_rows_[std::size_t(t) + 1] - colour_rows_[std::size_t(t)]
                                  : evenShare(shape_.H, t + 1, team) - evenShare(shape_.H, t, team);
    if (rows < 2 * kBand) return false;
  }
  return true;
}

// A team's rows follow the time they take (balanceShares): where the limit acts, near the pins of a hanging cloth, a
// row takes several times as long as where it does not. From kParallelItems points: on smaller cloths the clocks and
// the barriers they need cost more than the waits they save (CS184's 50 x 50 files on a team 4% slower, 128^2 no
// faster).
bool GridPath::followsColourTimes() const {
  return inTeam() && (colour_rows_fixed_ || (long long)shape_.W * shape_.H >= kParallelItems);
}

// This thread's rows of the colours [y0, y1), and whether every thread's are the even split of every other pass
// (teamShare's). Where they are not, a thread's rows were not all its own in the pass before, nor are they in the
// next: the caller puts a barrier before the first colour and after the copy out.
bool GridPath::colourRows(bool follow, long long& y0, long long& y1) {
  teamShare(0, shape_.H, y0, y1);
  if (!follow) return true;
  const int team = teamSize(), thread = teamThread();
  if (colour_rows_.size() != std::size_t(team) + 1 || colour_rows_.back() != shape_.H) {
    teamBarrier();  // no thread reads them until every thread has seen they need making
    if (thread == 0) {
      colour_rows_.resize(std::size_t(team) + 1);
      for (int t = 0; t <= team; ++t)
        colour_rows_[std::size_t(t)] = evenShare(shape_.H, t, team);
      colour_seconds_.assign(std::size_t(team), 0);
      colour_per_row_.assign(std::size_t(team), -1);
    }
    teamBarrier();
  }
  y0 = colour_rows_[std::size_t(thread)];
  y1 = colour_rows_[std::size_t(thread) + 1];
  for (int t = 1; t < team; ++t)
    if (colour_rows_[std::size_t(t)] != evenShare(shape_.H, t, team)) return false;
  return true;
}

}  // namespace drape
