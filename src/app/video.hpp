// `render --video`: the frames this run wrote, encoded by ffmpeg into a video written as every other output
// is. ffmpeg never opens the target: it writes a temporary of ours in the target's folder (.drape-XXXXXX
// plus the target's extension, from which it picks the container), made and locked before the first frame
// is rendered (so a folder that cannot take the video is refused before any work), and renamed over the
// target once ffmpeg has succeeded. A link planted at the target meanwhile is replaced, not written
// through; a failure or a kill leaves the target as it was. The frames reach ffmpeg through a pipe, in
// order (no folder of links to clean up), and ffmpeg dies with drape (app/process.hpp).
#pragma once

#include "core/atomic_file.hpp"

#include <filesystem>
#include <vector>

namespace drape {

class VideoOutput {
 public:
  // Checks the target (core/atomic_file.hpp) and makes its temporary: throws OutputError.
  explicit VideoOutput(const std::filesystem::path& target);

  // Runs ffmpeg on the PNG files `frames` at `fps` and renames the result over the target. Throws
  // CommandError (status 1) when ffmpeg fails, OutputError when the rename does.
  void encode(const std::vector<std::filesystem::path>& frames, double fps);

 private:
  std::filesystem::path target_;
  TemporaryFile temporary_;
};

}  // namespace drape
