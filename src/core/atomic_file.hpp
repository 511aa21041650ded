// Output files are written whole or not at all, and only over a regular file or nothing: the contents
// go to a fresh temporary file beside the target (mkstemp: O_EXCL, so nothing planted there is
// followed), are flushed to disk, and the temporary is renamed over the target. A symbolic link, FIFO,
// device or directory at the target is refused, never written through or replaced.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace drape {

// what() is one line naming the file. badTarget(): the path itself is unusable (not a regular file,
// no such directory), which is bad input; otherwise writing failed (a full disk, an I/O error).
class OutputError : public std::runtime_error {
 public:
  OutputError(bool bad_target, const std::string& message) : std::runtime_error(message), bad_target_(bad_target) {}
  bool badTarget() const { return bad_target_; }

 private:
  bool bad_target_;
};

// Checks, before any work, that writeFileAtomically(path, ...) may write there: the target is a regular
// file or absent and its directory exists. Throws OutputError(bad_target = true) otherwise.
void checkOutputFile(const std::filesystem::path& path);

void writeFileAtomically(const std::filesystem::path& path, std::string_view contents);

// The same for a file written in parts, so that a long one never has to be held in memory: the parts go to
// the temporary as they come, commit() flushes it and renames it over the target. Destroyed uncommitted
// (a failure, a stopped run), it leaves nothing. Throws OutputError as writeFileAtomically does.
class StreamedFile {
 public:
  explicit StreamedFile(const std::filesystem::path& path);
  ~StreamedFile();
  StreamedFile(const StreamedFile&) = delete;
  StreamedFile& operator=(const StreamedFile&) = delete;

  void append(std::string_view part);
  // Rewrites bytes already appended, at `offset` from the start (a header's field once its value is known).
  void overwrite(std::size_t offset, std::string_view bytes);
  std::size_t size() const { return size_; }
  void commit();

 private:
  std::filesystem::path target_;
  std::string name_;
  int fd_ = -1;
  std::size_t size_ = 0;
  bool committed_ = false;
};

// Writes all of `data` to `fd`, through short writes and EINTR. False (errno set) on failure.
bool writeAll(int fd, std::string_view data);

}  // namespace drape
