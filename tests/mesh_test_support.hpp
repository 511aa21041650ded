// OBJ meshes written for tests: a quad grid, a triangulated disc, and whatever text a bad case needs.
#pragma once

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "test_paths.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace drape::mesh_test {

namespace fs = std::filesystem;

inline const fs::path& tempDir() {
  static const test::TempDir dir("drape_mesh_test_");
  return dir.path();
}

inline fs::path writeFile(const std::string& name, const std::string& text) {
  const fs::path p = tempDir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

// n x n vertices over `size` metres in the plane y = height, as quads (or two triangles each), with UVs.
inline std::string gridObj(int n, double size, double height, bool quads) {
  std::string s;
  for (int z = 0; z < n; ++z)
    for (int x = 0; x < n; ++x)
      s += fmt::format("v {} {} {}\n", x * size / (n - 1), height, z * size / (n - 1));
  for (int z = 0; z < n; ++z)
    for (int x = 0; x < n; ++x)
      s += fmt::format("vt {} {}\n", double(x) / (n - 1), double(z) / (n - 1));
  for (int z = 0; z + 1 < n; ++z)
    for (int x = 0; x + 1 < n; ++x) {
      const int a = z * n + x + 1, b = a + 1, c = a + n + 1, d = a + n;
      if (quads)
        s += fmt::format("f {0}/{0} {1}/{1} {2}/{2} {3}/{3}\n", a, d, c, b);
      else
        s += fmt::format("f {0}/{0} {1}/{1} {2}/{2}\nf {0}/{0} {2}/{2} {3}/{3}\n", a, d, c, b);
    }
  return s;
}

// A disc of `rings` rings around a centre vertex, radius r, in the plane y = height: an irregular
// triangle mesh (ring k has 6k vertices, every other ring turned by half a step), consistently wound.
inline std::string discObj(int rings, double r, double height, glm::dvec2 centre = {0, 0}) {
  std::string s = fmt::format("v {} {} {}\n", centre.x, height, centre.y);
  auto angle = [](int k, int i) { return (i + 0.5 * (k % 2)) / (6.0 * k); };  // in turns
  int inner_first = 1, inner_count = 1;                                       // 1-based; ring 0 is the centre
  for (int k = 1; k <= rings; ++k) {
    const int count = 6 * k, first = inner_first + inner_count;
    for (int i = 0; i < count; ++i) {
      const double a = 2.0 * M_PI * angle(k, i);
      s += fmt::format("v {} {} {}\n", centre.x + r * k / rings * std::cos(a), height,
                       centre.y + r * k / rings * std::sin(a));
    }
    auto outer = [&](int i) { return first + i % count; };
    auto inner = [&](int j) { return inner_first + j % inner_count; };
    if (k == 1) {
      for (int i = 0; i < count; ++i)
        s += fmt::format("f {} {} {}\n", outer(i), outer(i + 1), inner_first);
    } else {
      // Zip the two rings together in angle order.
      for (int i = 0, j = 0; i < count || j < inner_count;) {
        if (j == inner_count || (i < count && angle(k, i + 1) <= angle(k - 1, j + 1))) {
          s += fmt::format("f {} {} {}\n", outer(i), outer(i + 1), inner(j));
          ++i;
        } else {
          s += fmt::format("f {} {} {}\n", inner(j + 1), inner(j), outer(i));
          ++j;
        }
      }
    }
    inner_first = first;
    inner_count = count;
  }
  return s;
}

}  // namespace drape::mesh_test
