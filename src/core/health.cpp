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
  for (std::size_t k = 0; k < topo.springs.size(); ++k) {
    const Spring& s = topo.springs[k];
    if (!cloth.springEnabled(s.type)) continue;
    const double most = stretch * s.rest;
    // Float squares of lengths this short lose their relative precision (subnormals): the scan decides there
    if (!(most * most >= 0x1p-60)) q.usable = false;
    q.index.push_back(std::uint32_t(k));
    q.a.push_back(s.a);
    q.b.push_back(s.b);
    q.limit2.push_back(float(most * most * (1.0 - 0x1p-20)));  // rounded either way: still within the margin
  }
  return q;
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
  const std::size_t first = std::size_t(std::lower_bound(q.index.begin(), q.index.end(), s0) - q.index.begin());
  const std::size_t last = std::size_t(std::lower_bound(q.index.begin(), q.index.end(), s1) - q.index.begin());
  for (std::size_t k = first; k < last; ++k) {
    const glm::vec3 d = x[q.a[k]] - x[q.b[k]];
    ok &= d.x * d.x + d.y * d.y + d.z * d.z <= q.limit2[k];
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
