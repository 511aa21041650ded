#include "core/atomic_file.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <mutex>
#include <set>
#include <string_view>
#include <system_error>
#include <vector>

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

[[noreturn]] void failIo(const std::filesystem::path& target, const char* what) {
  fail(false, target, std::string(what) + ": " + std::strerror(errno));
}

// .drape-XXXXXX, then nothing or an extension of letters and digits.
bool namedAsOurs(const std::string& name) {
  constexpr std::string_view prefix = ".drape-";
  if (name.size() < prefix.size() + 6 || name.compare(0, prefix.size(), prefix) != 0) return false;
  const auto alnum = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0; };
  const std::size_t end = prefix.size() + 6;
  if (!std::all_of(name.begin() + std::ptrdiff_t(prefix.size()), name.begin() + std::ptrdiff_t(end), alnum))
    return false;
  if (name.size() == end) return true;
  return name[end] == '.' && name.size() > end + 1 && name.size() <= end + 9 &&
         std::all_of(name.begin() + std::ptrdiff_t(end) + 1, name.end(), alnum);
}

// Removes `name` in the open folder `dir` if it is a stale temporary of ours.
void removeIfStale(int dir, const std::string& name, std::time_t now) {
  const int fd = ::openat(dir, name.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) return;
  struct stat st {};
  // Locked by a live process, or written to within the minute: in use. flock's lock goes with its owner,
  // however the owner ends.
  if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_uid == ::geteuid() && now - st.st_mtime > 60 &&
      ::flock(fd, LOCK_EX | LOCK_NB) == 0)
    ::unlinkat(dir, name.c_str(), 0);
  ::close(fd);
}

}  // namespace

TemporaryFile::TemporaryFile(const std::filesystem::path& target, const std::string& suffix) : target_(target) {
  const std::filesystem::path dir = directoryOf(target);
  removeStaleTemporaries(dir);
  path_ = (dir / ".drape-XXXXXX").string() + suffix;
  // O_CLOEXEC: a child started later (ffmpeg, the plot) must not inherit a half-written file.
  fd_ = ::mkostemps(path_.data(), int(suffix.size()), O_CLOEXEC);
  if (fd_ < 0)
    fail(errno == ENOENT || errno == ENOTDIR || errno == EACCES || errno == EROFS || errno == EPERM, target_,
         std::string("cannot create a file in its directory: ") + std::strerror(errno));
  ::flock(fd_, LOCK_EX | LOCK_NB);  // new, so no one else holds it
  // mkstemp makes 0600; an output file gets the permissions any new file would.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd_, 0666 & ~mask);
}

TemporaryFile::~TemporaryFile() {
  // Unlinked before its lock goes with the descriptor: no one can take it for a stale one and remove it.
  if (!renamed_) ::unlink(path_.c_str());
  if (fd_ >= 0) ::close(fd_);
}

bool TemporaryFile::stillOurs() const {
  struct stat named {
  }, ours{};
  return ::lstat(path_.c_str(), &named) == 0 && ::fstat(fd_, &ours) == 0 && S_ISREG(named.st_mode) &&
         named.st_dev == ours.st_dev && named.st_ino == ours.st_ino;
}

void TemporaryFile::renameOverTarget() {
  // Before the rename: after a crash the target holds the old or the new contents, never a hole.
  if (::fsync(fd_) != 0) failIo(target_, "write failed (fsync)");
  if (::rename(path_.c_str(), target_.c_str()) != 0) {
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

void removeStaleTemporaries(const std::filesystem::path& dir) {
  static std::mutex mutex;
  static std::set<std::string> swept;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    std::error_code error;
    const std::filesystem::path key = std::filesystem::absolute(dir, error).lexically_normal();
    if (!swept.insert(error ? dir.string() : key.string()).second) return;
  }
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  DIR* listing = ::fdopendir(fd);
  if (!listing) {
    ::close(fd);
    return;
  }
  const std::time_t now = std::time(nullptr);
  std::vector<std::string> names;
  while (const dirent* entry = ::readdir(listing))
    if (namedAsOurs(entry->d_name)) names.emplace_back(entry->d_name);
  for (const std::string& name : names)
    removeIfStale(::dirfd(listing), name, now);
  ::closedir(listing);
}

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

// checkOutputFile runs before the temporary is made: a bad target is refused before anything is created.
StreamedFile::StreamedFile(const std::filesystem::path& path)
    : target_((checkOutputFile(path), path)), temporary_(path) {}

void StreamedFile::append(std::string_view part) {
  if (!writeAll(temporary_.fd(), part)) failIo(target_, "write failed");
  size_ += part.size();
}

void StreamedFile::overwrite(std::size_t offset, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::pwrite(temporary_.fd(), bytes.data(), bytes.size(), off_t(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n == 0) errno = EIO;
    if (n <= 0) failIo(target_, "write failed");
    bytes.remove_prefix(std::size_t(n));
    offset += std::size_t(n);
  }
}

// A link or FIFO planted at the target since the check is replaced, not followed: rename() never follows
// the name it replaces.
void StreamedFile::commit() {
  temporary_.renameOverTarget();
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
