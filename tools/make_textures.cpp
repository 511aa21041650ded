// Writes Drape's textures (no third-party images): a woven plaid fabric, cobblestone and brick height
// maps, and a sky cube map whose sun sits where the renderer's default light is. Deterministic: the
// same build writes the same bytes, so the committed PNGs can be regenerated and compared.
//
//   make_textures [OUT_DIR]   (default: the source tree's textures/)
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace {

// splitmix64: a fixed, portable sequence (std distributions differ between standard libraries).
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }  // [0, 1)

 private:
  std::uint64_t state_;
};

// Hash of integer lattice coordinates to [0, 1), the basis of the value noise below.
double latticeValue(int x, int y, int z, std::uint64_t seed) {
  std::uint64_t h = seed ^ (std::uint64_t(std::uint32_t(x)) * 0x8da6b343ULL) ^
                    (std::uint64_t(std::uint32_t(y)) * 0xd8163841ULL) ^
                    (std::uint64_t(std::uint32_t(z)) * 0xcb1ab31fULL);
  return double(Random(h).next() >> 11) * (1.0 / 9007199254740992.0);
}

double smooth(double t) {
  return t * t * (3.0 - 2.0 * t);
}

// Trilinear value noise; `period` > 0 wraps x and y so that 2D images tile.
double valueNoise(glm::dvec3 p, std::uint64_t seed, int period = 0) {
  glm::dvec3 f = glm::floor(p);
  glm::dvec3 t = p - f;
  auto wrap = [&](int v) { return period > 0 ? ((v % period) + period) % period : v; };
  double result = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    int dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
    double w = (dx ? smooth(t.x) : 1.0 - smooth(t.x)) * (dy ? smooth(t.y) : 1.0 - smooth(t.y)) *
               (dz ? smooth(t.z) : 1.0 - smooth(t.z));
    result += w * latticeValue(wrap(int(f.x) + dx), wrap(int(f.y) + dy), int(f.z) + dz, seed);
  }
  return result;
}

// Fractal sum of octaves, in [0, 1).
double fbm(glm::dvec3 p, std::uint64_t seed, int octaves, int period = 0) {
  double sum = 0.0, amplitude = 0.5, norm = 0.0;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * valueNoise(p, seed + std::uint64_t(o) * 7919, period);
    norm += amplitude;
    amplitude *= 0.5;
    p *= 2.0;
    period *= 2;
  }
  return sum / norm;
}

std::uint8_t toByte(double v) {
  return std::uint8_t(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
}

struct Image {
  int width, height, channels;
  std::vector<std::uint8_t> pixels;
  Image(int w, int h, int c) : width(w), height(h), channels(c), pixels(std::size_t(w) * h * c) {}
  void set(int x, int y, glm::dvec3 rgb) {
    std::uint8_t* p = &pixels[(std::size_t(y) * width + x) * channels];
    p[0] = toByte(rgb.r);
    if (channels >= 3) {
      p[1] = toByte(rgb.g);
      p[2] = toByte(rgb.b);
    }
  }
};

bool writePng(const std::filesystem::path& file, const Image& image) {
  int ok = stbi_write_png(file.string().c_str(), image.width, image.height, image.channels, image.pixels.data(),
                          image.width * image.channels);
  if (!ok) {
    std::fprintf(stderr, "make_textures: %s: cannot write\n", file.string().c_str());
    return false;
  }
  std::printf("wrote %s (%dx%d, %d channel%s)\n", file.string().c_str(), image.width, image.height, image.channels,
              image.channels > 1 ? "s" : "");
  return true;
}

// Plain weave: warp (vertical) and weft (horizontal) threads alternate over and under. Thread colours
// follow a tartan sett, the same sequence in both directions, so the crossings mix two colours.
Image makeFabric(int size) {
  constexpr int kThread = 4;  // pixels per thread; size / kThread threads, an even number so it tiles
  const std::array<glm::dvec3, 4> palette = {glm::dvec3{0.55, 0.08, 0.10}, glm::dvec3{0.08, 0.12, 0.30},
                                             glm::dvec3{0.06, 0.22, 0.12}, glm::dvec3{0.90, 0.82, 0.55}};
  // Sett: colour index per run of threads, repeated; the total (64 threads) divides size / kThread.
  const std::array<std::pair<int, int>, 6> sett = {{{0, 20}, {1, 12}, {0, 4}, {3, 2}, {2, 18}, {1, 8}}};
  auto threadColour = [&](int thread) {
    int period = 0;
    for (auto [c, n] : sett)
      period += n;
    int t = thread % period;
    for (auto [c, n] : sett) {
      if (t < n) return palette[c];
      t -= n;
    }
    return palette[0];
  };
  Image image(size, size, 3);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      int tx = x / kThread, ty = y / kThread;
      bool warp_on_top = ((tx + ty) & 1) == 0;
      // Position across the visible thread, -1..1, shades it like a cylinder.
      double across =
          warp_on_top ? (x % kThread + 0.5) / kThread * 2.0 - 1.0 : (y % kThread + 0.5) / kThread * 2.0 - 1.0;
      double along =
          warp_on_top ? (y % kThread + 0.5) / kThread * 2.0 - 1.0 : (x % kThread + 0.5) / kThread * 2.0 - 1.0;
      double shade = 0.62 + 0.38 * std::sqrt(std::max(0.0, 1.0 - across * across)) * (1.0 - 0.25 * along * along);
      glm::dvec3 colour = warp_on_top ? threadColour(tx) : threadColour(ty);
      double fibre = 0.9 + 0.2 * fbm({x * 0.5, y * 0.5, 0.0}, 11, 2, size / 2);
      image.set(x, y, colour * shade * fibre);
    }
  }
  return image;
}

// Cobblestones: a Voronoi diagram on a torus (distances wrap, so the map tiles), each cell a rounded
// dome that falls to the mortar at its border, with a little surface roughness.
Image makeCobblestone(int size) {
  constexpr int kGrid = 8;  // jittered seed per cell of an 8x8 grid
  Random random(1995);
  std::vector<glm::dvec2> seeds;
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i)
      seeds.push_back((glm::dvec2(i, j) + 0.2 + 0.6 * glm::dvec2(random.uniform(), random.uniform())) / double(kGrid));
  Image image(size, size, 1);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      glm::dvec2 p = (glm::dvec2(x, y) + 0.5) / double(size);
      double d1 = 1e9, d2 = 1e9;
      for (const glm::dvec2& s : seeds) {
        glm::dvec2 d = glm::abs(p - s);
        d = glm::min(d, 1.0 - d);  // toroidal distance
        double dist = glm::length(d);
        if (dist < d1) {
          d2 = d1;
          d1 = dist;
        } else if (dist < d2) {
          d2 = dist;
        }
      }
      // (d2 - d1) is zero on a cell border and grows towards the centre.
      double edge = (d2 - d1) * kGrid;
      double dome = std::sqrt(std::clamp(edge / 0.45, 0.0, 1.0));
      double rough = fbm({p.x * 32.0, p.y * 32.0, 0.0}, 77, 3, 32);
      image.set(x, y, glm::dvec3(0.08 + 0.8 * dome + 0.12 * (rough - 0.5) * dome));
    }
  }
  return image;
}

// Bricks in running bond: 8 courses of 4 bricks, every other course shifted by half a brick.
Image makeBrick(int size) {
  constexpr int kCourses = 8, kBricksPerCourse = 4;
  const double mortar = 0.06;  // of a course height
  Image image(size, size, 1);
  Random random(1889);
  std::vector<double> brick_height(kCourses * kBricksPerCourse);
  for (double& h : brick_height)
    h = 0.8 + 0.15 * random.uniform();
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      double v = (y + 0.5) / size * kCourses;
      int course = int(v);
      double u = (x + 0.5) / size * kBricksPerCourse + ((course & 1) ? 0.5 : 0.0);
      int brick = int(u) % kBricksPerCourse;
      double fu = u - std::floor(u), fv = v - course;
      // Distance to the nearest joint in course heights (a brick is twice as long as high).
      double du = std::min(fu, 1.0 - fu) * 2.0, dv = std::min(fv, 1.0 - fv);
      double joint = std::min(du, dv);
      double bevel = std::clamp((joint - mortar) / 0.08, 0.0, 1.0);
      double rough = fbm({x * 0.25, y * 0.25, 0.0}, 5, 3, size / 4);
      double height = bevel > 0.0 ? 0.15 + bevel * (brick_height[course * kBricksPerCourse + brick] - 0.15) : 0.1;
      image.set(x, y, glm::dvec3(height + 0.1 * (rough - 0.5)));
    }
  }
  return image;
}

// Direction through texel (s, t) of a cube face, by the GL cube map face table (spec 8.13) inverted:
// image row 0 is t = 0, which the GL convention puts at the top of the side faces.
glm::dvec3 cubeDirection(int face, double s, double t) {
  double sc = 2.0 * s - 1.0, tc = 2.0 * t - 1.0;
  switch (face) {
    case 0:
      return {1.0, -tc, -sc};
    case 1:
      return {-1.0, -tc, sc};
    case 2:
      return {sc, 1.0, tc};
    case 3:
      return {sc, -1.0, -tc};
    case 4:
      return {sc, -tc, 1.0};
    default:
      return {-sc, -tc, -1.0};
  }
}

glm::dvec3 skyColour(glm::dvec3 dir) {
  dir = glm::normalize(dir);
  const glm::dvec3 sun_dir = glm::normalize(glm::dvec3(0.5, 2.0, 2.0));  // the renderer's default light
  const glm::dvec3 zenith{0.18, 0.36, 0.75}, horizon{0.72, 0.82, 0.92}, ground{0.33, 0.30, 0.26};
  double elevation = dir.y;
  glm::dvec3 colour;
  if (elevation >= 0.0) {
    colour = glm::mix(horizon, zenith, std::pow(elevation, 0.5));
    // Clouds: noise projected onto a flat layer above the viewer, thinning towards the horizon.
    glm::dvec2 layer = glm::dvec2(dir.x, dir.z) / (elevation + 0.15) * 1.5;
    double c = fbm({layer.x, layer.y, 3.7}, 42, 5);
    double cover = glm::smoothstep(0.5, 0.75, c) * glm::smoothstep(0.0, 0.25, elevation);
    colour = glm::mix(colour, glm::dvec3(0.97, 0.97, 0.98), 0.85 * cover);
  } else {
    // Ground: fields of slightly different tones, seen in perspective on a flat layer below the viewer.
    glm::dvec2 layer = glm::dvec2(dir.x, dir.z) / (-elevation + 0.05) * 2.0;
    double field = fbm({layer.x, layer.y, 9.1}, 7, 4);
    glm::dvec3 land = glm::mix(ground, glm::dvec3(0.30, 0.36, 0.22), glm::smoothstep(0.35, 0.65, field));
    colour = glm::mix(horizon * 0.8, land, std::pow(std::min(1.0, -elevation * 4.0), 0.6));
  }
  double cos_sun = glm::dot(dir, sun_dir);
  double angle = std::acos(std::clamp(cos_sun, -1.0, 1.0));
  double disc = 1.0 - glm::smoothstep(0.035, 0.045, angle);
  double glow = std::exp(-angle * 6.0) * 0.45;
  colour += glm::dvec3(1.0, 0.9, 0.7) * glow + glm::dvec3(1.0, 0.98, 0.9) * disc;
  return glm::min(colour, glm::dvec3(1.0));
}

Image makeSkyFace(int face, int size) {
  Image image(size, size, 3);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      image.set(x, y, skyColour(cubeDirection(face, (x + 0.5) / size, (y + 0.5) / size)));
  return image;
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path out =
      argc > 1 ? std::filesystem::path(argv[1]) : std::filesystem::path(DRAPE_SOURCE_DIR) / "textures";
  std::error_code error;
  std::filesystem::create_directories(out, error);
  if (error) {
    std::fprintf(stderr, "make_textures: %s: %s\n", out.string().c_str(), error.message().c_str());
    return 1;
  }
  stbi_write_png_compression_level = 9;
  bool ok = writePng(out / "fabric.png", makeFabric(256));
  ok = writePng(out / "cobblestone_height.png", makeCobblestone(256)) && ok;
  ok = writePng(out / "brick_height.png", makeBrick(256)) && ok;
  const std::array<const char*, 6> faces = {"px", "nx", "py", "ny", "pz", "nz"};
  for (int f = 0; f < 6; ++f)
    ok = writePng(out / ("sky_" + std::string(faces[f]) + ".png"), makeSkyFace(f, 256)) && ok;
  return ok ? 0 : 1;
}
