// The cloth written out per frame (--export, --format, --every on `simulate` and `render`), for Blender,
// Houdini and usdview: an OBJ (points, normals, UVs, triangles) or a binary little-endian PLY per exported
// frame, or one ASCII USD file whose Mesh prim has time-sampled points, normals and extent, one sample per
// exported frame, written as the run goes (its memory does not grow with the frames) and kept up to the last
// good frame when the run blows up. Every file is written whole or not at all (core/atomic_file).
#pragma once

#include "core/atomic_file.hpp"
#include "core/metrics.hpp"
#include "core/scene.hpp"
#include "core/topology.hpp"

#include <filesystem>
#include <memory>
#include <string>

namespace drape {

enum class ExportFormat { Obj, Ply, Usda };

// Where --export PATH --format F writes. `--format` decides the extension: PATH's own extension, if it is
// one of .obj, .ply and .usda, is replaced (and must agree with F), anything else stays part of the name.
// Without --format the extension says it. A folder (PATH ending in '/', or an existing directory) gets
// cloth_NNNN.obj (or .ply), or cloth.usda, inside it; OBJ unless --format says otherwise.
struct ExportTarget {
  std::filesystem::path stem;  // the files' path without the frame number and the extension
  ExportFormat format = ExportFormat::Obj;
  // The sequence's file for a frame (stem, "_", the frame in 4 digits or more, the extension: cloth_0090.obj,
  // the numbering Blender's and Houdini's sequence importers expect), or the one USD file.
  std::filesystem::path file(int frame) const;
};
// Throws CommandError (bad input) naming --export or --format.
ExportTarget resolveExport(const std::string& path, const std::string& format);

class UsdaStream;

class ClothExport {
 public:
  // Makes the target's missing folders and checks that the files may be written there (nothing but a
  // regular file is in the way), before the run. `last_frame`: the last frame the run will export, which
  // the USD file's header says until a blow-up makes it earlier.
  ClothExport(const ExportTarget& target, const Scene& scene, const Topology& topology, int last_frame);
  ~ClothExport();
  ClothExport(const ClothExport&) = delete;
  ClothExport& operator=(const ClothExport&) = delete;

  // One exported frame: writes its OBJ or PLY file now, or appends it to the USD file.
  void add(int frame, const Positions& x);
  // Puts the USD file in place with the frames added so far (nothing for sequences). Called at the end of
  // the run, and on a blow-up, which keeps the good frames.
  void finish();
  int written() const { return written_; }
  int lastFrame() const { return last_; }  // the last frame added; -1 before the first

 private:
  ExportTarget target_;
  const Topology* topology_;
  std::unique_ptr<UsdaStream> usda_;
  int last_ = -1, written_ = 0;
};

// On a blow-up: puts what was exported in place (the USD file up to the last good frame) and says so, as the
// end of the blow-up's line ("; --export keeps frames 0 to 40").
std::string keepExport(ClothExport& exporter);

// The file contents, public for the tests.
std::string objText(const Topology& topology, const Positions& x, int frame);
std::string plyBytes(const Topology& topology, const Positions& x);
// Vertex normals summed over the cloth's whole faces (a quad's normal is the cross product of its
// diagonals, so it does not depend on how its triangles split it; render/cloth_surface.hpp), unit; +y where
// a point has no area.
std::vector<glm::dvec3> vertexNormals(const Topology& topology, const Positions& x);

}  // namespace drape
