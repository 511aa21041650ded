// Input files (scenes, OBJ meshes, bench baselines) opened one way everywhere, so that no name makes drape
// wait or read without end: a regular file's size is checked against the caller's limit before a byte is
// read; a FIFO or pipe is opened without waiting for a writer (one with none reads as nothing) and read
// no further than the limit; a directory, device or socket is refused. Problems are one short phrase
// ("cannot open: no such file", "too large: ..."); the caller puts the file's name in front.
#pragma once

#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace drape {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class InputFile {
 public:
  // `what` names the kind of file in the size message ("a scene", "an OBJ file").
  InputFile(const std::filesystem::path& path, long long max_bytes, const std::string& what);
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  // Up to `size` bytes; 0 at the end. Throws InputError on a read error or once the bytes read pass
  // max_bytes (a FIFO, whose size is not known before).
  std::size_t read(char* buffer, std::size_t size);

 private:
  [[noreturn]] void tooLarge() const;

  int fd_ = -1;
  bool fifo_ = false;
  long long max_bytes_ = 0;
  long long read_ = 0;
  std::string what_;
};

// The whole file, through InputFile's checks.
std::string readInputFile(const std::filesystem::path& path, long long max_bytes, const std::string& what);

// "512 MiB", "16 MiB", "100 KiB", "12 bytes": a limit as the messages and docs state it.
std::string describeBytes(long long bytes);

}  // namespace drape
