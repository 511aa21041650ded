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
  StreamedFile file(path);
  file.append(contents);
  file.commit();
}

StreamedFile::StreamedFile(const std::filesystem::path& path) : target_(path) {
  checkOutputFile(path);
  name_ = (directoryOf(path) / ".drape-XXXXXX").string();
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

StreamedFile::~StreamedFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) ::unlink(name_.c_str());
}

void StreamedFile::append(std::string_view part) {
  if (!writeAll(fd_, part)) fail(false, target_, std::string("write failed: ") + std::strerror(errno));
  size_ += part.size();
}

void StreamedFile::overwrite(std::size_t offset, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::pwrite(fd_, bytes.data(), bytes.size(), off_t(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail(false, target_, std::string("write failed: ") + std::strerror(n == 0 ? EIO : errno));
    bytes.remove_prefix(std::size_t(n));
    offset += std::size_t(n);
  }
}

void StreamedFile::commit() {
  // Before the rename: after a crash the target holds the old or the new contents, never a hole.
  if (::fsync(fd_) != 0) fail(false, target_, std::string("write failed (fsync): ") + std::strerror(errno));
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail(false, target_, std::string("write failed (close): ") + std::strerror(errno));
  // A link or FIFO planted at the target since the check is replaced, not followed: rename() never follows
  // the name it replaces. A directory may have appeared there since the check.
  if (::rename(name_.c_str(), target_.c_str()) != 0)
    fail(errno == EISDIR || errno == ENOTDIR, target_, std::string("cannot replace: ") + std::strerror(errno));
  committed_ = true;
  // Best effort: the new directory entry on disk too (some file systems cannot fsync a directory).
  const int dir = ::open(directoryOf(target_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
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
