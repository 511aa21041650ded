// Whether two arrays hold the same bytes: the tests' check that two ways of computing a run agree exactly.
#pragma once

#include <cstring>
#include <vector>

namespace drape::test {

template <class V>
bool sameBytes(const std::vector<V>& a, const std::vector<V>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(V)) == 0;
}

}  // namespace drape::test
