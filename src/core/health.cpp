#include "core/health.hpp"

#include <algorithm>
#include <cmath>

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

Health scanHealth(const Topology& topo, const ClothSpec& cloth, const std::vector<glm::dvec3>& x,
                  const std::vector<glm::dvec3>& v, const HealthLimits& limits) {
  Health h;
  const auto raise = [&h](unsigned flag, std::size_t point) {
    h.flags |= flag;
    if (h.first_point < 0 || (long long)point < h.first_point) h.first_point = (long long)point;
  };
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!finite(x[i]) || (i < v.size() && !finite(v[i]))) {
      raise(Health::kNonFinite, i);
    } else if (std::max({std::abs(x[i].x), std::abs(x[i].y), std::abs(x[i].z)}) > limits.sane_bound) {
      raise(Health::kOutOfBounds, i);
    }
  }
  // The GPU compares length > (1 + max_strain) * rest in float; written the same way here so that the
  // two disagree only for a spring within rounding of the limit.
  const double stretch = 1.0 + limits.max_strain;
  for (const Spring& s : topo.springs) {
    if (!cloth.springEnabled(s.type)) continue;
    if (glm::distance(x[s.a], x[s.b]) > stretch * s.rest) {
      raise(Health::kOverstretched, s.a);
      raise(Health::kOverstretched, s.b);
    }
  }
  return h;
}

}  // namespace drape
