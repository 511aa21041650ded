#include "app/video.hpp"

#include "app/command_error.hpp"
#include "app/process.hpp"

#include <fcntl.h>
#include <fmt/core.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

namespace drape {

namespace {

// While drape feeds ffmpeg: a write to a pipe ffmpeg closed (it failed) is EPIPE, not a signal that ends
// drape before it can say what happened.
class IgnoreBrokenPipes {
 public:
  IgnoreBrokenPipes() {
    struct sigaction ignore {};
    ignore.sa_handler = SIG_IGN;
    ::sigaction(SIGPIPE, &ignore, &old_);
  }
  ~IgnoreBrokenPipes() { ::sigaction(SIGPIPE, &old_, nullptr); }
  IgnoreBrokenPipes(const IgnoreBrokenPipes&) = delete;
  IgnoreBrokenPipes& operator=(const IgnoreBrokenPipes&) = delete;

 private:
  struct sigaction old_ {};
};

enum class Fed { All, Refused };

// Copies the file into `pipe`. Refused: ffmpeg stopped reading (it failed; its status says why).
Fed feed(const std::filesystem::path& frame, int pipe) {
  // O_NOFOLLOW: the frame this run wrote, not whatever a link planted in its place points to.
  const int fd = ::open(frame.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0)
    throw CommandError(kExitFailure,
                       fmt::format("--video: cannot read the frame {}: {}", frame.string(), std::strerror(errno)));
  char buffer[1 << 16];
  Fed fed = Fed::All;
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int error = errno;
      ::close(fd);
      throw CommandError(kExitFailure,
                         fmt::format("--video: cannot read the frame {}: {}", frame.string(), std::strerror(error)));
    }
    if (n == 0) break;
    if (!writeAll(pipe, std::string_view(buffer, std::size_t(n)))) {
      fed = Fed::Refused;
      break;
    }
  }
  ::close(fd);
  return fed;
}

// The target is checked before its temporary is made beside it.
const std::filesystem::path& checked(const std::filesystem::path& target) {
  checkOutputFile(target);
  return target;
}

}  // namespace

VideoOutput::VideoOutput(const std::filesystem::path& target)
    : target_(checked(target)), temporary_(target, target.extension().string()) {}

void VideoOutput::encode(const std::vector<std::filesystem::path>& frames, double fps) {
  // No shell: the names reach ffmpeg as they are. An absolute path, so that a name starting with '-' is
  // not an option and one with a ':' is not a protocol (e.g. pipe:). -y: the temporary exists (empty).
  const std::string output = std::filesystem::absolute(temporary_.path()).string();
  const std::vector<std::string> command = {"ffmpeg",
                                            "-nostdin",
                                            "-loglevel",
                                            "error",
                                            "-y",
                                            "-f",
                                            "image2pipe",
                                            "-framerate",
                                            fmt::format("{:.6g}", fps),
                                            "-c:v",
                                            "png",
                                            "-i",
                                            "pipe:0",
                                            "-c:v",
                                            "libx264",
                                            "-pix_fmt",
                                            "yuv420p",
                                            "-vf",
                                            "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                                            output};
  int status = 0;
  {
    const IgnoreBrokenPipes ignore;
    ChildProcess ffmpeg(command, {.stdin_pipe = true});
    for (const std::filesystem::path& frame : frames)
      if (ffmpeg.stdinFd() < 0 || feed(frame, ffmpeg.stdinFd()) == Fed::Refused) break;
    status = ffmpeg.wait();
  }
  if (status != 0)
    throw CommandError(kExitFailure,
                       fmt::format("--video: ffmpeg failed to write {} (exit status {})", target_.string(), status));
  if (!temporary_.stillOurs())
    throw CommandError(kExitFailure, fmt::format("--video: {}: the temporary {} was replaced while ffmpeg wrote it; "
                                                 "nothing written",
                                                 target_.string(), temporary_.path()));
  temporary_.renameOverTarget();
  fmt::print(stderr, "render: wrote {} ({} frames)\n", target_.string(), frames.size());
}

}  // namespace drape
