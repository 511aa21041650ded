// `drape penetration`: how deep a cloth exported by `drape simulate --export PATH.obj` (any build's) is inside
// the scene's spheres and mesh obstacles, frame by frame, against the exact surfaces (core/penetration.hpp).
#include "app/commands.hpp"
#include "app/options.hpp"

#include "core/obj_reader.hpp"
#include "core/penetration.hpp"

#include <fmt/core.h>

#include <fstream>
#include <string>
#include <vector>

namespace drape {

namespace {

struct PenetrationOptions {
  std::string scene;
  std::vector<std::string> frames;
  double spacing_mm = 1.0;
};

// The frame number `drape simulate --export` writes on the first line ("# drape cloth, frame N: ..."), or
// -1 for a file that does not say.
int frameOf(const std::string& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  int frame = -1;
  if (std::sscanf(line.c_str(), "# drape cloth, frame %d:", &frame) != 1) return -1;
  return frame;
}

struct Deepest {
  double depth = 0.0;
  int frame = -1;
  int which = -1;
};

void runPenetration(const PenetrationOptions& o) {
  const Scene scene = loadScene(o.scene);
  if (scene.spheres.empty() && scene.meshes.empty())
    throw CommandError(kExitBadInput, fmt::format("{}: no sphere or mesh obstacle to measure against", o.scene));
  const Topology topology = buildTopology(scene.cloth);
  const PenetrationGauge gauge(scene, topology, o.spacing_mm * 1e-3);
  fmt::print(
      "# {}: cloth points and triangles inside its spheres and meshes (exact surfaces; triangles sampled {:g} mm "
      "apart), mm. nearest: the closest cloth point's signed distance (exact within 2 field cells of a mesh, the "
      "field's estimate beyond); inside: how many points are inside; vertex, triangle: the deepest point and the "
      "deepest "
      "point of any triangle, and which\n",
      o.scene, o.spacing_mm);
  fmt::print("{:>6} {:>10} {:>7} {:>10} {:>7} {:>10} {:>9}\n", "frame", "nearest", "inside", "vertex", "point",
             "triangle", "triangle#");
  int contact = -1, last = -1;
  Deepest vertex, surface;
  Penetration at_last;
  for (std::size_t k = 0; k < o.frames.size(); ++k) {
    const std::string& file = o.frames[k];
    PolygonMesh mesh;
    try {
      mesh = readObj(file, {kMaxClothPoints, " (the most a cloth may have)"});
    } catch (const MeshError& e) {
      throw CommandError(kExitBadInput, fmt::format("{}: {}", file, e.what()));
    }
    if (mesh.positions.size() != topology.initial_positions.size())
      throw CommandError(kExitBadInput, fmt::format("{}: {} vertices, but the cloth of {} has {} points", file,
                                                    mesh.positions.size(), o.scene, topology.pointCount()));
    const int frame = frameOf(file) >= 0 ? frameOf(file) : int(k);
    const Penetration p = gauge.measure(mesh.positions);
    fmt::print("{:>6} {:>10.3f} {:>7} {:>10.3f} {:>7} {:>10.3f} {:>9}\n", frame, p.nearest * 1e3, p.vertices_inside,
               p.vertex * 1e3, p.vertex_index, p.surface * 1e3, p.surface_triangle);
    // Contact: a point within the cloth's thickness of an obstacle. Depths count from then on.
    if (contact < 0 && p.nearest <= scene.cloth.thickness) contact = frame;
    if (contact < 0) continue;
    if (p.vertex > vertex.depth || vertex.frame < 0) vertex = {p.vertex, frame, p.vertex_index};
    if (p.surface > surface.depth || surface.frame < 0) surface = {p.surface, frame, p.surface_triangle};
    last = frame;
    at_last = p;
  }
  if (contact < 0) {
    fmt::print("contact      none (no point came within the cloth's thickness, {:g} mm, of an obstacle)\n",
               scene.cloth.thickness * 1e3);
    return;
  }
  fmt::print("contact      from frame {} (a point within the cloth's thickness, {:g} mm, of an obstacle)\n", contact,
             scene.cloth.thickness * 1e3);
  fmt::print("vertex       deepest {:.3f} mm (frame {}, point {}); at frame {}: {:.3f} mm, {} points inside\n",
             vertex.depth * 1e3, vertex.frame, vertex.which, last, at_last.vertex * 1e3, at_last.vertices_inside);
  fmt::print("triangle     deepest {:.3f} mm (frame {}, triangle {}); at frame {}: {:.3f} mm\n", surface.depth * 1e3,
             surface.frame, surface.which, last, at_last.surface * 1e3);
}

}  // namespace

void addPenetrationCommand(CLI::App& app) {
  auto o = std::make_shared<PenetrationOptions>();
  CLI::App* cmd = app.add_subcommand(
      "penetration", "How deep exported cloth frames (simulate --export X.obj) are inside the scene's obstacles");
  cmd->add_option("scene", o->scene, "Scene JSON file the frames were simulated from")->required();
  cmd->add_option("frames", o->frames, "Exported OBJ frames, in order")->required();
  cmd->add_option("--spacing", o->spacing_mm, "Largest distance between the samples of a triangle, mm")
      ->check(positiveNumberUpTo(1000.0))
      ->capture_default_str();
  cmd->callback([o] { runPenetration(*o); });
}

}  // namespace drape
