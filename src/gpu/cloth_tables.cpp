#include "gpu/cloth_tables.hpp"

#include "core/derived.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace drape::gpu {

std::vector<PointMass> pointMasses(const Scene& scene, const Topology& topo) {
  const ClothSpec& c = scene.cloth;
  std::vector<PointMass> masses(std::size_t(topo.pointCount()), PointMass{});
  for (std::size_t i = 0; i < masses.size(); ++i) {
    const float mass = float(derived::pointMass(c, topo, i));
    masses[i].weight = glm::vec4(glm::vec3(scene.sim.gravity) * mass, 1.0f / mass);
    masses[i].drag_area = float(derived::dragArea(scene.sim.wind.drag, c, topo, i));
    const auto& stencil = topo.normal_stencil[i];
    masses[i].normal_a = stencil[0];
    masses[i].normal_b = stencil[1];
    masses[i].normal_c = stencil[2];
    masses[i].normal_d = stencil[3];
  }
  return masses;
}

// The same float operations as CpuSolver<float>::refreshDerived and its passes.
SimParams simParams(const Scene& scene, const std::vector<PointMass>& masses, const ParamsInput& in) {
  const ClothSpec& c = scene.cloth;
  const drape::SimParams& sim = scene.sim;
  const WindSpec& wind = sim.wind;
  const float dt = float(sim.dt());
  const float thickness = float(c.thickness);
  SimParams p{};
  // A grid's points all have the same area, so the same weight: the kernels read it here instead of 48 bytes
  // of PointMass per point (UNIFORM_MASS).
  if (c.isGrid()) {
    p.weight = masses[0].weight;
    for (const PointMass& m : masses)
      if (m.weight != p.weight) throw std::logic_error("GpuSolver: a grid cloth's points differ in weight");
  }
  p.stiffness = glm::vec4(float(c.ks), float(c.ks), float(derived::bendingStiffness(c)), 0.0f);
  p.wind_velocity = glm::vec4(glm::vec3(wind.velocity), float(wind.turbulence));
  p.dt = dt;
  p.dt2 = dt * dt;
  p.keep = float(1.0 - c.damping / 100.0);
  p.thickness = thickness;
  p.inv_cell_size = 1.0f / (2.0f * thickness);  // as CpuSolver<float>::selfCollide rounds it
  // As CpuSolver<float>::selfCollide and CollisionPairs<float>::build compute them.
  const float range = 2.0f * thickness;
  const float margin = derived::pairSkin(in.pair_margin, range, in.shortest_spring);
  const float reach = range + margin;
  p.inv_pair_cell = 1.0f / reach;
  p.pair_reach = reach;
  p.pair_reach2 = reach * reach;
  p.pair_margin = margin;
  p.steps_per_frame = float(sim.steps_per_frame);
  p.stretch_limit = float(sim.stretch_limit);
  p.noise_scale = float(wind.noise_scale);
  p.noise_speed = float(wind.noise_speed);
  p.sane_bound = float(in.health.sane_bound);
  p.blow_up_stretch = float(1.0 + in.health.max_strain);
  for (int t = 0; t < kSpringTypeCount; ++t)
    p.alpha_tilde[t] = float(derived::xpbdAlphaTilde(c, sim, SpringType(t)));
  p.point_count = std::uint32_t(masses.size());
  p.bucket_count = in.buckets;
  p.bucket_mask = p.bucket_count - 1;
  p.scan_blocks = (p.bucket_count + kScanBlock - 1) / kScanBlock;
  return p;
}

Adjacency adjacency(const Topology& topo, const SceneNeeds& needs) {
  const std::size_t n = std::size_t(topo.pointCount());
  Adjacency a;
  a.offsets.assign(n + 1, 0);
  a.neighbors.reserve(topo.adjacency.size());
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t e = topo.offsets[i]; e < topo.offsets[i + 1]; ++e) {
      const drape::Neighbor& nb = topo.adjacency[e];
      if (needs.springs[std::size_t(nb.type)])
        a.neighbors.push_back({nb.other | (std::uint32_t(nb.type) << kNeighborIndexBits), float(nb.rest)});
    }
    a.offsets[i + 1] = std::uint32_t(a.neighbors.size());
  }
  return a;
}

ColouredSprings colouredSprings(const Topology& topo, const SpringColouring& colouring, const SceneNeeds& needs) {
  ColouredSprings out;
  out.springs.reserve(topo.springs.size());
  out.start.assign(1, 0);
  for (int c = 0; c < colouring.colourCount(); ++c) {
    for (std::uint32_t k = colouring.start[std::size_t(c)]; k < colouring.start[std::size_t(c) + 1]; ++k) {
      const Spring& s = topo.springs[colouring.springs[k]];
      if (needs.springs[std::size_t(s.type)]) out.springs.push_back({s.a, s.b, float(s.rest), std::uint32_t(s.type)});
    }
    out.start.push_back(std::uint32_t(out.springs.size()));
  }
  return out;
}

std::vector<ColourPartner> colourPartners(const Topology& topo, const SpringColouring& colouring,
                                          const SceneNeeds& needs) {
  const std::size_t n = std::size_t(topo.pointCount());
  const std::size_t colours = std::size_t(colouring.colourCount());
  std::vector<ColourPartner> partners(std::max<std::size_t>(colours * n, 1), {kNoPartner, 0.0f});
  for (std::size_t c = 0; c < colours; ++c)
    for (std::uint32_t k = colouring.start[c]; k < colouring.start[c + 1]; ++k) {
      const Spring& s = topo.springs[colouring.springs[k]];
      if (!needs.springs[std::size_t(s.type)]) continue;
      partners[c * n + s.a] = {s.b, float(s.rest)};
      partners[c * n + s.b] = {s.a, float(s.rest)};
    }
  return partners;
}

std::vector<Tether> tetherEntries(const Tethers& t) {
  static_assert(kNoTether == kNoAnchor);
  std::vector<Tether> entries(t.anchor.size());
  for (std::size_t k = 0; k < entries.size(); ++k)
    entries[k] = {t.anchor[k], float(t.rest[k])};
  return entries;
}

double shortestStructural(const Topology& topo) {
  double shortest = std::numeric_limits<double>::infinity();
  for (const Spring& s : topo.springs)
    if (s.type == SpringType::Structural) shortest = std::min(shortest, s.rest);
  return shortest;
}

bool mayHoldPairs(const Topology& topo, double range) {
  const double r = range * (1.0 + 1e-4);
  const std::vector<glm::dvec3>& x = topo.initial_positions;
  if (x.empty()) return false;
  // Along the axis the cloth spans most, so that the band of points within r of one along it is narrow.
  glm::dvec3 lo = x[0], hi = x[0];
  for (const glm::dvec3& p : x) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::dvec3 span = hi - lo;
  const int axis = span.x >= span.y && span.x >= span.z ? 0 : span.y >= span.z ? 1 : 2;
  std::vector<std::uint32_t> order(x.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return x[a][axis] < x[b][axis]; });
  for (std::size_t k = 0; k < order.size(); ++k)
    for (std::size_t l = k + 1; l < order.size() && x[order[l]][axis] - x[order[k]][axis] < r; ++l) {
      const glm::dvec3 d = x[order[l]] - x[order[k]];
      if (glm::dot(d, d) < r * r) return true;
    }
  return false;
}

std::vector<float> restPositions(const Topology& topo) {
  std::vector<float> out;
  out.reserve(3 * topo.initial_positions.size());
  for (const glm::dvec3& p : topo.initial_positions) {
    const glm::vec3 f(p);
    out.insert(out.end(), {f.x, f.y, f.z});
  }
  return out;
}

}  // namespace drape::gpu
