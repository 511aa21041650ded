// Writes the bundled OBJ meshes of scenes/meshes/ (no third-party models): obstacles that are closed and
// wound outward (a table with rounded edges, a torus, a mannequin of capsules, a sharp box) and two cloths
// (quad grids with UVs: the flag, and the square dropped on the box). Deterministic: the same build writes the same
// bytes, so the committed files can be regenerated and compared.
//
//   make_meshes [OUT_DIR]   (default: the source tree's scenes/meshes/)
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

struct Mesh {
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec2> uvs;  // empty, or one per position
  std::vector<std::vector<std::uint32_t>> faces;

  // Appends `part`, renumbering its faces.
  void add(const Mesh& part) {
    const auto base = std::uint32_t(positions.size());
    positions.insert(positions.end(), part.positions.begin(), part.positions.end());
    for (auto face : part.faces) {
      for (std::uint32_t& v : face)
        v += base;
      faces.push_back(face);
    }
  }
};

// A closed surface parameterised by (u, v) in [0, 1]^2, u around (periodic), v from pole to pole (a single
// vertex at each) or, for a torus, periodic too. Quads wound so that the surface faces outward when
// cross(dP/du, dP/dv) points out.
template <class Surface>
Mesh closedSurface(int around, int along, bool poles, Surface at) {
  Mesh m;
  const int rings = poles ? along - 1 : along;  // rings of `around` vertices
  auto vertex = [&](int i, int j) -> std::uint32_t {
    if (poles) {
      if (j == 0) return 0;
      if (j == along) return std::uint32_t(1 + rings * around);
      return std::uint32_t(1 + (j - 1) * around + (i % around));
    }
    return std::uint32_t((j % along) * around + (i % around));
  };
  if (poles) m.positions.push_back(at(0.0, 0.0));
  for (int j = poles ? 1 : 0; j < (poles ? along : along); ++j)
    for (int i = 0; i < around; ++i)
      m.positions.push_back(at(double(i) / around, double(j) / along));
  if (poles) m.positions.push_back(at(0.0, 1.0));
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      const std::uint32_t a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1), d = vertex(i, j + 1);
      if (poles && j == 0)
        m.faces.push_back({a, c, d});
      else if (poles && j == along - 1)
        m.faces.push_back({a, b, d});
      else
        m.faces.push_back({a, b, c, d});
    }
  return m;
}

// A box of half extents `half` with every edge and corner rounded to `radius`, centred at `centre`: the
// inner box grown by a sphere. A lattice on the outer box's surface, with `rounding` steps across each
// rounded band and the flat middle at about `spacing`, is moved onto the surface: each lattice point goes
// to its nearest point of the inner box plus `radius` in the direction it lies from there, so the flat
// faces stay flat and neighbouring faces share the vertices of the edge between them.
Mesh roundedBox(glm::dvec3 centre, glm::dvec3 half, double radius, int rounding, double spacing) {
  const glm::dvec3 inner = half - radius;
  std::vector<double> axes[3];
  for (int a = 0; a < 3; ++a) {
    const double h = inner[a];
    for (int k = rounding; k > 0; --k)
      axes[a].push_back(-h - radius * std::sin(glm::half_pi<double>() * k / rounding));
    const int middle = std::max(1, int(std::ceil(2.0 * h / spacing)));
    for (int k = 0; k <= middle; ++k)
      axes[a].push_back(-h + 2.0 * h * k / middle);
    for (int k = 1; k <= rounding; ++k)
      axes[a].push_back(h + radius * std::sin(glm::half_pi<double>() * k / rounding));
  }
  Mesh m;
  const std::size_t n[3] = {axes[0].size(), axes[1].size(), axes[2].size()};
  std::vector<std::int64_t> id(n[0] * n[1] * n[2], -1);
  auto vertex = [&](std::size_t i, std::size_t j, std::size_t k) {
    std::int64_t& v = id[(k * n[1] + j) * n[0] + i];
    if (v < 0) {
      v = std::int64_t(m.positions.size());
      const glm::dvec3 p(axes[0][i], axes[1][j], axes[2][k]);
      const glm::dvec3 q = glm::clamp(p, -inner, inner);
      const glm::dvec3 d = p - q;
      m.positions.push_back(centre + q + d / glm::length(d) * radius);
    }
    return std::uint32_t(v);
  };
  // The six faces of the lattice's shell, each wound outward.
  for (int axis = 0; axis < 3; ++axis) {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      const std::size_t fixed = side ? n[axis] - 1 : 0;
      auto at = [&](std::size_t p, std::size_t q) {
        std::size_t c[3];
        c[axis] = fixed;
        c[a1] = p;
        c[a2] = q;
        return vertex(c[0], c[1], c[2]);
      };
      for (std::size_t p = 0; p + 1 < n[a1]; ++p)
        for (std::size_t q = 0; q + 1 < n[a2]; ++q) {
          const std::uint32_t v00 = at(p, q), v10 = at(p + 1, q), v11 = at(p + 1, q + 1), v01 = at(p, q + 1);
          if (side)
            m.faces.push_back({v00, v10, v11, v01});
          else
            m.faces.push_back({v00, v01, v11, v10});
        }
    }
  }
  return m;
}

// A capsule from a to b of radius r: a cylinder with hemispherical ends.
Mesh capsule(glm::dvec3 a, glm::dvec3 b, double r, int around, int along) {
  const glm::dvec3 axis = glm::normalize(b - a);
  const glm::dvec3 side =
      glm::normalize(glm::cross(axis, std::fabs(axis.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0)));
  const glm::dvec3 other = glm::cross(axis, side);
  const double length = glm::distance(a, b);
  const double total = length + glm::pi<double>() * r;  // arc length pole to pole along a meridian
  return closedSurface(around, along, true, [&](double u, double v) {
    const double s = v * total, quarter = glm::half_pi<double>() * r;
    double height, radial;
    if (s < quarter) {
      const double t = s / r;  // angle from the pole at a
      height = -r * std::cos(t);
      radial = r * std::sin(t);
    } else if (s > quarter + length) {
      const double t = (s - quarter - length) / r;
      height = length + r * std::sin(t);
      radial = r * std::cos(t);
    } else {
      height = s - quarter;
      radial = r;
    }
    const double phi = -2.0 * glm::pi<double>() * u;
    return a + axis * height + (side * std::cos(phi) + other * std::sin(phi)) * radial;
  });
}

// A box with sharp edges: half extents `half`, its base centred at `base`, turned by `turn` radians about
// the vertical, as 6 quads.
Mesh box(glm::dvec3 base, glm::dvec3 half, double turn) {
  Mesh m;
  const double c = std::cos(turn), s = std::sin(turn);
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 p(k & 1 ? half.x : -half.x, k & 2 ? 2.0 * half.y : 0.0, k & 4 ? half.z : -half.z);
    m.positions.push_back(base + glm::dvec3(c * p.x + s * p.z, p.y, -s * p.x + c * p.z));
  }
  m.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  return m;
}

// A square cloth of n x n vertices, `size` metres a side, centred above the origin at `height`, as quads
// with UVs.
Mesh squareCloth(int n, double size, double height) {
  Mesh m;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.positions.push_back({size * (double(i) / (n - 1) - 0.5), height, size * (double(j) / (n - 1) - 0.5)});
      m.uvs.push_back({double(i) / (n - 1), double(j) / (n - 1)});
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const auto a = std::uint32_t(j * n + i), w = std::uint32_t(n);
      m.faces.push_back({a, a + w, a + w + 1, a + 1});
    }
  return m;
}

Mesh torus(glm::dvec3 centre, double major, double minor, int around, int along) {
  return closedSurface(around, along, false, [&](double u, double v) {
    const double phi = 2.0 * glm::pi<double>() * u, theta = -2.0 * glm::pi<double>() * v;
    const double ring = major + minor * std::cos(theta);
    return centre + glm::dvec3(ring * std::cos(phi), minor * std::sin(theta), ring * std::sin(phi));
  });
}

// The signed volume, to check (and fix) that a closed mesh faces outward.
double volume(const Mesh& m) {
  double v = 0;
  for (const auto& f : m.faces)
    for (std::size_t k = 1; k + 1 < f.size(); ++k)
      v += glm::dot(m.positions[f[0]], glm::cross(m.positions[f[k]], m.positions[f[k + 1]])) / 6.0;
  return v;
}

Mesh outward(Mesh m) {
  if (volume(m) < 0)
    for (auto& f : m.faces)
      std::reverse(f.begin(), f.end());
  return m;
}

void write(const std::filesystem::path& file, const Mesh& m, const char* what) {
  std::string s = std::string("# ") + what + " (tools/make_meshes.cpp)\n";
  char line[160];
  for (const glm::dvec3& p : m.positions) {
    std::snprintf(line, sizeof line, "v %.6f %.6f %.6f\n", p.x, p.y, p.z);
    s += line;
  }
  for (const glm::dvec2& t : m.uvs) {
    std::snprintf(line, sizeof line, "vt %.6f %.6f\n", t.x, t.y);
    s += line;
  }
  for (const auto& f : m.faces) {
    s += "f";
    for (std::uint32_t v : f)
      s += m.uvs.empty() ? " " + std::to_string(v + 1) : " " + std::to_string(v + 1) + "/" + std::to_string(v + 1);
    s += "\n";
  }
  std::ofstream(file, std::ios::binary) << s;
  std::printf("%s: %zu vertices, %zu faces\n", file.string().c_str(), m.positions.size(), m.faces.size());
}

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path out = argc > 1 ? argv[1] : std::filesystem::path(DRAPE_SOURCE_DIR) / "scenes" / "meshes";
  std::filesystem::create_directories(out);

  // A 1.6 m x 1.0 m table, its top 75 cm above the floor; the legs stop 5 mm short of the top so that the
  // parts do not overlap (they may, but then the drawing shows the seam).
  Mesh table;
  table.add(outward(roundedBox({0, 0.75, 0}, {0.8, 0.025, 0.5}, 0.02, 4, 0.05)));
  for (double x : {-0.7, 0.7})
    for (double z : {-0.4, 0.4})
      table.add(outward(roundedBox({x, 0.36, z}, {0.03, 0.36, 0.03}, 0.015, 3, 0.08)));
  write(out / "table.obj", table, "table: a rounded top on four rounded legs, floor at y = 0");

  write(out / "torus.obj", outward(torus({0, 0.12, 0}, 0.32, 0.12, 72, 28)),
        "torus: major radius 0.32 m, tube 0.12 m, lying on the floor");

  // A mannequin of overlapping capsules, about 1.75 m tall, arms out: the inside is their union.
  Mesh mannequin;
  const int around = 24, along = 24;
  mannequin.add(outward(capsule({0, 0.95, 0}, {0, 1.35, 0}, 0.16, around, along)));          // torso
  mannequin.add(outward(capsule({0, 1.58, 0}, {0, 1.62, 0}, 0.11, around, along)));          // head
  mannequin.add(outward(capsule({-0.14, 1.38, 0}, {-0.78, 1.36, 0}, 0.05, around, along)));  // arms
  mannequin.add(outward(capsule({0.14, 1.38, 0}, {0.78, 1.36, 0}, 0.05, around, along)));
  mannequin.add(outward(capsule({-0.09, 0.08, 0}, {-0.1, 0.9, 0}, 0.07, around, along)));  // legs
  mannequin.add(outward(capsule({0.09, 0.08, 0}, {0.1, 0.9, 0}, 0.07, around, along)));
  write(out / "mannequin.obj", mannequin, "mannequin: six capsules, arms out, feet on the floor");

  // The flag: 1.5 m x 1 m in the plane z = 0, its pole edge at x = 0, as 30 x 20 quads with UVs.
  Mesh flag;
  const int W = 31, H = 21;
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < W; ++i) {
      flag.positions.push_back({1.5 * i / (W - 1), 1.0 + 1.0 * j / (H - 1), 0.0});
      flag.uvs.push_back({double(i) / (W - 1), double(j) / (H - 1)});
    }
  for (int j = 0; j + 1 < H; ++j)
    for (int i = 0; i + 1 < W; ++i) {
      const auto a = std::uint32_t(j * W + i);
      flag.faces.push_back({a, a + 1, a + 1 + std::uint32_t(W), a + std::uint32_t(W)});
    }
  write(out / "flag.obj", flag, "flag: 1.5 m x 1 m, 30 x 20 quads, pole edge at x = 0, from y = 1 to 2");
  write(out / "pole.obj", outward(capsule({-0.03, 0.0, 0}, {-0.03, 2.05, 0}, 0.02, 16, 24)),
        "flag pole: a capsule of radius 2 cm beside the flag's edge");

  // The box drop (scenes/box_drop.json, tools/box-drop): a 30 cm x 15 cm x 30 cm box on the floor, turned by
  // 15 degrees so that its edges cross the cloth's rows obliquely, and a 60 cm cloth of 21 x 21 points (3 cm
  // apart) 1 m above its top.
  write(out / "box.obj", outward(box({0.01, 0.0, -0.005}, {0.15, 0.075, 0.15}, glm::radians(15.0))),
        "box: 30 cm x 15 cm x 30 cm, sharp edges, on the floor, turned 15 degrees about the vertical");
  write(out / "drop_cloth.obj", squareCloth(21, 0.6, 1.15),
        "drop cloth: 60 cm x 60 cm, 20 x 20 quads (3 cm), 1 m above the box's top");
  return 0;
}
