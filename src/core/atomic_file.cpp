#include "core/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace drape {

namespace {

std::string describeType(mode_t mode) {
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::filesystem::path directoryOf(const std::filesystem::path& path) {
  const std::filesystem::path parent = path.parent_path();
  return parent.empty() ? std::filesystem::path(".") : parent;
}

[[noreturn]] void fail(bool bad_target, const std::filesystem::path& path, const std::string& problem) {
  throw OutputError(bad_target, path.string() + ": " + problem);
}

// Owns the temporary file until it is renamed into place; removes it on any failure.
class Temporary {
 public:
  explicit Temporary(const std::filesystem::path& target) : target_(target) {
    name_ = (directoryOf(target) / ".drape-XXXXXX").string();
    // O_CLOEXEC: a child started later (ffmpeg, the plot) must not inherit a half-written file.
    fd_ = ::mkostemp(name_.data(), O_CLOEXEC);
    if (fd_ < 0)
      fail(errno == ENOENT || errno == ENOTDIR || errno == EACCES || errno == EROFS, target_,
           std::string("cannot create a file in its directory: ") + std::strerror(errno));
    // mkstemp makes 0600; an output file gets the permissions any new file would.
    const mode_t mask = ::umask(0);
    ::umask(mask);
    ::fchmod(fd_, 0666 & ~mask);
  }
  ~Temporary() {
    if (fd_ >= 0) ::close(fd_);
    if (!renamed_) ::unlink(name_.c_str());
  }
  Temporary(const Temporary&) = delete;
  Temporary& operator=(const Temporary&) = delete;

  void write(std::string_view contents) {
    if (!writeAll(fd_, contents)) failIo("write failed");
    // Before the rename: after a crash the target holds the old or the new contents, never a hole.
    if (::fsync(fd_) != 0) failIo("write failed (fsync)");
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) failIo("write failed (close)");
  }

  void renameOverTarget() {
    if (::rename(name_.c_str(), target_.c_str()) != 0) {
      // A directory may have appeared at the target since the check.
      fail(errno == EISDIR || errno == ENOTDIR, target_, std::string("cannot replace: ") + std::strerror(errno));
    }
    renamed_ = true;
    // Best effort: the new directory entry on disk too (some file systems cannot fsync a directory).
    const int dir = ::open(directoryOf(target_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
      ::fsync(dir);
      ::close(dir);
    }
  }

 private:
  [[noreturn]] void failIo(const char* what) const {
    fail(false, target_, std::string(what) + ": " + std::strerror(errno));
  }

  std::filesystem::path target_;
  std::string name_;
  int fd_ = -1;
  bool renamed_ = false;
};

}  // namespace

void checkOutputFile(const std::filesystem::path& path) {
  if (path.empty()) fail(true, path, "empty output path");
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0) {
    if (!S_ISREG(st.st_mode)) fail(true, path, "is " + describeType(st.st_mode) + ", not a regular file; not written");
  } else if (errno != ENOENT) {
    fail(true, path, std::strerror(errno));
  }
  const std::filesystem::path dir = directoryOf(path);
  if (::stat(dir.c_str(), &st) != 0) fail(true, path, "no such directory " + dir.string());
  if (!S_ISDIR(st.st_mode)) fail(true, path, dir.string() + " is not a directory");
}

void writeFileAtomically(const std::filesystem::path& path, std::string_view contents) {
  checkOutputFile(path);
  Temporary temporary(path);
  temporary.write(contents);
  // A link or FIFO planted at the target since the check is replaced, not followed: rename() never
  // follows the name it replaces.
  temporary.renameOverTarget();
}

bool writeAll(int fd, std::string_view data) {
  while (!data.empty()) {
    const ssize_t n = ::write(fd, data.data(), data.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = EIO;
      return false;
    }
    data.remove_prefix(std::size_t(n));
  }
  return true;
}

}  // namespace drape
