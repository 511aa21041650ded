#include "core/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace drape {

namespace {

std::string openProblem(int error) {
  if (error == ENOENT) return "cannot open: no such file";
  return std::string("cannot open: ") + std::strerror(error);
}

}  // namespace

std::string describeBytes(long long bytes) {
  if (bytes >= (1LL << 20) && bytes % (1LL << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
  if (bytes >= (1LL << 10) && bytes % (1LL << 10) == 0) return std::to_string(bytes >> 10) + " KiB";
  return std::to_string(bytes) + (bytes == 1 ? " byte" : " bytes");
}

InputFile::InputFile(const std::filesystem::path& path, long long max_bytes, const std::string& what)
    : max_bytes_(max_bytes), what_(what) {
  // O_NONBLOCK only for the open: a FIFO then opens at once, writer or not; it is cleared again below, so
  // that a FIFO with a writer is read as the writer writes. O_NOCTTY: a terminal never becomes ours.
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
  if (fd_ < 0) {
    // A directory cannot be opened for reading on some systems (EISDIR); the same words as below.
    if (errno == EISDIR) throw InputError("cannot open: is a directory, not a file");
    throw InputError(openProblem(errno));
  }
  struct stat st {};
  if (::fstat(fd_, &st) != 0) {
    const int error = errno;
    ::close(fd_);
    throw InputError(openProblem(error));
  }
  const auto refuse = [&](const std::string& problem) {
    ::close(fd_);
    fd_ = -1;
    throw InputError(problem);
  };
  if (S_ISDIR(st.st_mode)) refuse("cannot open: is a directory, not a file");
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) refuse("cannot open: is a device, not a file");
  if (S_ISSOCK(st.st_mode)) refuse("cannot open: is a socket, not a file");
  fifo_ = S_ISFIFO(st.st_mode);
  if (!fifo_ && st.st_size > max_bytes_) tooLarge();
  const int flags = ::fcntl(fd_, F_GETFL);
  if (flags < 0 || ::fcntl(fd_, F_SETFL, flags & ~O_NONBLOCK) != 0) refuse(openProblem(errno));
}

InputFile::~InputFile() {
  if (fd_ >= 0) ::close(fd_);
}

void InputFile::tooLarge() const {
  throw InputError("too large for " + what_ + " (more than " + describeBytes(max_bytes_) + ")");
}

std::size_t InputFile::read(char* buffer, std::size_t size) {
  for (;;) {
    const ssize_t n = ::read(fd_, buffer, size);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw InputError(std::string("cannot read: ") + std::strerror(errno));
    // A FIFO nobody opened for writing reads as empty at once: say so rather than "no faces".
    if (n == 0 && fifo_ && read_ == 0) throw InputError("cannot read: a FIFO with nothing written to it");
    read_ += n;
    // A regular file that grew since it was opened is held to the same limit.
    if (read_ > max_bytes_) tooLarge();
    return std::size_t(n);
  }
}

std::string readInputFile(const std::filesystem::path& path, long long max_bytes, const std::string& what) {
  InputFile file(path, max_bytes, what);
  std::string text;
  char piece[1 << 16];
  while (const std::size_t n = file.read(piece, sizeof piece))
    text.append(piece, n);
  return text;
}

}  // namespace drape
