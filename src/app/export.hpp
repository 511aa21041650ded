// The cloth written out per frame (--export, --format, --every on `simulate` and `render`), for Blender,
// Houdini and usdview: an OBJ (points, normals, UVs, triangles) or a binary little-endian PLY per exported
// frame, or one ASCII USD file whose Mesh prim has time-sampled points, one sample per exported frame.
// Every file is written whole or not at all (core/atomic_file), and every path is checked before the run.
#pragma once

#include "core/metrics.hpp"
#include "core/scene.hpp"
#include "core/topology.hpp"

#include <filesystem>
#include <string>

namespace drape {

enum class ExportFormat { Obj, Ply, Usda };

// "obj", "ply", "usda", or "" for the extension of `path`. Throws CommandError (bad input) otherwise.
ExportFormat parseExportFormat(const std::string& format, const std::filesystem::path& path);

// A sequence's file for one frame: PATH's stem, "_" and the frame in 4 digits (more when needed), PATH's
// extension: cloth.obj -> cloth_0090.obj, the numbering Blender's and Houdini's sequence importers expect.
std::filesystem::path sequenceFile(const std::filesystem::path& path, int frame);

class ClothExport {
 public:
  // Checks that the files may be written (their directory exists; nothing but a regular file is there).
  // The sequence's files are only known by pattern, so their directory is checked, and each file as it
  // is written.
  ClothExport(std::filesystem::path path, ExportFormat format, const Scene& scene, const Topology& topology);

  // One exported frame: writes its OBJ or PLY file now, or keeps the points for the USD file.
  void add(int frame, const Positions& x);
  // Writes the USD file (nothing for sequences).
  void finish();
  int written() const { return written_; }

 private:
  std::filesystem::path path_;
  ExportFormat format_;
  const Scene* scene_;
  const Topology* topology_;
  std::string samples_;  // USD: the time samples so far
  int first_ = -1, last_ = -1, written_ = 0;
};

// The file contents, public for the tests.
std::string objText(const Topology& topology, const Positions& x, int frame);
std::string plyBytes(const Topology& topology, const Positions& x);
// Area-weighted vertex normals of the triangles (unit; +y where a point has no area).
std::vector<glm::dvec3> vertexNormals(const Topology& topology, const Positions& x);

}  // namespace drape
