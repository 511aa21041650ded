#include "core/health.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace drape {

namespace {

bool finite(const glm::dvec3& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

}  // namespace

std::string Health::describe() const {
  if (ok()) return {};
  std::string what;
  const auto add = [&what](const char* text) { what += (what.empty() ? "" : ", ") + std::string(text); };
  if (flags & kNonFinite) add("non-finite position or displacement");
  if (flags & kOutOfBounds) add("a point beyond the sane bound");
  if (flags & kOverstretched) add("a spring stretched beyond its blow-up strain");
  return what + " (first at point " + std::to_string(first_point) + ")";
}

void Health::merge(const Health& part) {
  flags |= part.flags;
  if (part.first_point >= 0 && (first_point < 0 || part.first_point < first_point)) first_point = part.first_point;
}

Health scanHealth(const Topology& topo, const ClothSpec& cloth, const std::vector<glm::dvec3>& x,
                  const std::vector<glm::dvec3>& v, const HealthLimits& limits) {
  return scanHealthPart(topo, cloth, x, v, limits, 0, x.size(), 0, topo.springs.size());
}

template <class P>
Health scanHealthPart(const Topology& topo, const ClothSpec& cloth, const std::vector<P>& x, const std::vector<P>& v,
                      const HealthLimits& limits, std::size_t p0, std::size_t p1, std::size_t s0, std::size_t s1) {
  Health h;
  const auto raise = [&h](unsigned flag, std::size_t point) {
    h.flags |= flag;
    if (h.first_point < 0 || (long long)point < h.first_point) h.first_point = (long long)point;
  };
  for (std::size_t i = p0; i < p1; ++i) {
    const glm::dvec3 p(x[i]);
    if (!finite(p) || (i < v.size() && !finite(glm::dvec3(v[i])))) {
      raise(Health::kNonFinite, i);
    } else if (std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) > limits.sane_bound) {
      raise(Health::kOutOfBounds, i);
    }
  }
  // The GPU compares length > (1 + max_strain) * rest in float; here the squares in double (no square root a
  // spring), so that the two disagree only for a spring within rounding of the limit. NaN compares false
  // either way.
  const double stretch = 1.0 + limits.max_strain;
  for (std::size_t k = s0; k < s1; ++k) {
    const Spring& s = topo.springs[k];
    if (!cloth.springEnabled(s.type)) continue;
    const glm::dvec3 d = glm::dvec3(x[s.a]) - glm::dvec3(x[s.b]);
    const double most = stretch * s.rest;
    if (glm::dot(d, d) > most * most) {
      raise(Health::kOverstretched, s.a);
      raise(Health::kOverstretched, s.b);
    }
  }
  return h;
}

QuickHealth quickHealth(const Topology& topo, const ClothSpec& cloth, const HealthLimits& limits) {
  QuickHealth q;
  q.bound = float(limits.sane_bound);
  if (double(q.bound) > limits.sane_bound) q.bound = std::nextafter(q.bound, 0.0f);
  q.usable = true;
  const double stretch = 1.0 + limits.max_strain;
  float run_most = 0;  // the largest limit of the last run's springs
  for (std::size_t k = 0; k < topo.springs.size(); ++k) {
    const Spring& s = topo.springs[k];
    if (!cloth.springEnabled(s.type)) continue;
    const double most = stretch * s.rest;
    // Float squares of lengths this short lose their relative precision (subnormals): the scan decides there
    if (!(most * most >= 0x1p-60)) q.usable = false;
    const float limit2 = quickLimit2(s.rest, limits);
    const auto step = std::int32_t(std::int64_t(s.b) - std::int64_t(s.a));
    if (!q.runs.empty()) {
      QuickHealth::Run& run = q.runs.back();
      const float least = std::min(run.limit2, limit2), largest = std::max(run_most, limit2);
      if (run.first + run.count == k && run.a + run.count == s.a && run.step == step &&
          double(largest) <= double(least) * (1 + QuickHealth::kRunSpread)) {
        ++run.count;
        run.limit2 = least;
        run_most = largest;
        continue;
      }
    }
    q.runs.push_back({std::uint32_t(k), 1, s.a, step, limit2});
    run_most = limit2;
  }
  return q;
}

float quickLimit2(double rest, const HealthLimits& limits) {
  const double most = (1.0 + limits.max_strain) * rest;
  return float(most * most * (1.0 - 0x1p-20));  // rounded either way: still within the margin
}

bool quickHealthy(const QuickHealth& q, const std::vector<glm::vec3>& x, const std::vector<glm::vec3>& v,
                  std::size_t p0, std::size_t p1, std::size_t s0, std::size_t s1) {
  if (!q.usable) return false;
  // No early exit: the loops are reductions the compiler vectorises. A NaN fails every comparison.
  bool ok = true;
  const float* xs = &x.data()->x;
  for (std::size_t k = 3 * p0; k < 3 * p1; ++k)
    ok &= std::abs(xs[k]) <= q.bound;
  const float* vs = v.empty() ? nullptr : &v.data()->x;
  for (std::size_t k = 3 * p0; vs && k < 3 * std::min(p1, v.size()); ++k)
    ok &= std::abs(vs[k]) <= std::numeric_limits<float>::max();
  // The runs that hold springs [s0, s1), each from the first of them
  auto run = std::upper_bound(q.runs.begin(), q.runs.end(), s0,
                              [](std::size_t k, const QuickHealth::Run& r) { return k < r.first; });
  if (run != q.runs.begin()) --run;
  for (; run != q.runs.end() && run->first < s1; ++run) {
    const std::size_t from = std::max<std::size_t>(run->first, s0) - run->first;
    const std::size_t to = std::min<std::size_t>(run->first + run->count, s1) - run->first;
    const glm::vec3* ends_a = x.data() + run->a;
    const glm::vec3* ends_b = ends_a + run->step;
    const float limit2 = run->limit2;
    for (std::size_t k = from; k < to; ++k) {
      const glm::vec3 d = ends_a[k] - ends_b[k];
      ok &= d.x * d.x + d.y * d.y + d.z * d.z <= limit2;
    }
  }
  return ok;
}

template Health scanHealthPart(const Topology&, const ClothSpec&, const std::vector<glm::dvec3>&,
                               const std::vector<glm::dvec3>&, const HealthLimits&, std::size_t, std::size_t,
                               std::size_t, std::size_t);
template Health scanHealthPart(const Topology&, const ClothSpec&, const std::vector<glm::vec3>&,
                               const std::vector<glm::vec3>&, const HealthLimits&, std::size_t, std::size_t,
                               std::size_t, std::size_t);

}  // namespace drape
