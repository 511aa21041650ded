// Output files are written whole or not at all, and only over a regular file or nothing: the contents
// go to a fresh temporary file beside the target (mkstemp: O_EXCL, so nothing planted there is
// followed), are flushed to disk, and the temporary is renamed over the target. A symbolic link, FIFO,
// device or directory at the target is refused, never written through or replaced.
//
// Every temporary of drape's is named .drape-XXXXXX[.ext] and locked (flock) by the process that made it
// for as long as it is in use. A drape killed with SIGKILL leaves its temporaries behind, unlocked: the
// next drape that writes into that folder removes them (removeStaleTemporaries).
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

// Writes all of `data` to `fd`, through short writes and EINTR. False (errno set) on failure.
bool writeAll(int fd, std::string_view data);

// A fresh temporary of ours beside `target`: ".drape-XXXXXX" plus `suffix` (an extension a child program
// reads the format from), made with O_EXCL and locked until this object goes; removed then unless
// renamed over the target. Throws OutputError (bad_target when the folder cannot take a new file: missing,
// not writable, read-only), so making one checks that the target's folder is writable.
class TemporaryFile {
 public:
  TemporaryFile(const std::filesystem::path& target, const std::string& suffix = "");
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  int fd() const { return fd_; }
  const std::string& path() const { return path_; }
  // Whether `path()` still names this file: a name can be replaced while a child program writes it.
  bool stillOurs() const;
  // fsync, then rename over the target (never following what is there) and fsync its folder.
  void renameOverTarget();

 private:
  std::filesystem::path target_;
  std::string path_;
  int fd_ = -1;
  bool renamed_ = false;
};

// The same for a file written in parts, so that a long one never has to be held in memory: the parts go to
// the temporary as they come, commit() flushes it and renames it over the target. Destroyed uncommitted
// (a failure, a stopped run), it leaves nothing. Throws OutputError as writeFileAtomically does.
class StreamedFile {
 public:
  explicit StreamedFile(const std::filesystem::path& path);
  StreamedFile(const StreamedFile&) = delete;
  StreamedFile& operator=(const StreamedFile&) = delete;

  void append(std::string_view part);
  // Rewrites bytes already appended, at `offset` from the start (a header's field once its value is known).
  void overwrite(std::size_t offset, std::string_view bytes);
  std::size_t size() const { return size_; }
  void commit();

 private:
  std::filesystem::path target_;
  TemporaryFile temporary_;
  std::size_t size_ = 0;
};

// Removes, once per folder and process, the temporaries in `dir` a killed drape left: files named as ours,
// owned by this user, locked by no process and untouched for a minute (a temporary is locked from a
// moment after it is made, so a minute spares one just made).
void removeStaleTemporaries(const std::filesystem::path& dir);

}  // namespace drape
