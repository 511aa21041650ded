// The output writer against hostile targets: links, FIFOs, devices, directories, a full disk.
#include "core/atomic_file.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace drape {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class AtomicFileTest : public ::testing::Test {
 protected:
  fs::path dir = fs::temp_directory_path() / ("drape_atomic_" + std::to_string(::getpid()));
  void SetUp() override {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }

  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir))
      names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

  // Expects a refusal that names the target and leaves it as it was.
  void expectRefused(const fs::path& target) {
    try {
      writeFileAtomically(target, "new contents");
      FAIL() << "wrote to " << target;
    } catch (const OutputError& e) {
      EXPECT_TRUE(e.badTarget()) << e.what();
      EXPECT_NE(std::string(e.what()).find(target.string()), std::string::npos) << e.what();
    }
  }
};

TEST_F(AtomicFileTest, WritesAndReplacesARegularFileLeavingNothingElse) {
  writeFileAtomically(dir / "out.json", "first");
  EXPECT_EQ(slurp(dir / "out.json"), "first");
  writeFileAtomically(dir / "out.json", "second, longer");
  EXPECT_EQ(slurp(dir / "out.json"), "second, longer");
  EXPECT_EQ(entries(), std::vector<std::string>{"out.json"}) << "no temporary file is left";
  const mode_t mask = ::umask(0);
  ::umask(mask);
  EXPECT_EQ(fs::status(dir / "out.json").permissions(), fs::perms(0666 & ~mask)) << "permissions of a new file";
}

TEST_F(AtomicFileTest, RefusesASymbolicLinkAndLeavesItsTargetAlone) {
  std::ofstream(dir / "victim") << "precious";
  fs::create_symlink(dir / "victim", dir / "out.json");
  expectRefused(dir / "out.json");
  EXPECT_EQ(slurp(dir / "victim"), "precious");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "out.json")));
}

TEST_F(AtomicFileTest, APlantedLinkAtTheOldTemporaryNameIsNotFollowed) {
  // The writer used to write <out>.partial, wherever a link there pointed.
  std::ofstream(dir / "victim") << "precious";
  fs::create_symlink(dir / "victim", dir / "out.json.partial");
  writeFileAtomically(dir / "out.json", "output");
  EXPECT_EQ(slurp(dir / "victim"), "precious");
  EXPECT_EQ(slurp(dir / "out.json"), "output");
}

TEST_F(AtomicFileTest, RefusesAFifoWithoutBlocking) {
  ASSERT_EQ(::mkfifo((dir / "out.json").c_str(), 0600), 0);
  expectRefused(dir / "out.json");
  EXPECT_TRUE(fs::is_fifo(dir / "out.json"));
}

TEST_F(AtomicFileTest, RefusesADeviceAndLeavesItADevice) {
  // A copy of /dev/full's node, so that a failing run cannot replace the machine's own.
  const fs::path device = dir / "full";
  if (::mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 7)) != 0) GTEST_SKIP() << "mknod: " << std::strerror(errno);
  expectRefused(device);
  EXPECT_TRUE(fs::is_character_file(device));
}

TEST_F(AtomicFileTest, RefusesADirectoryAndAMissingDirectory) {
  fs::create_directory(dir / "out.json");
  expectRefused(dir / "out.json");
  expectRefused(dir / "missing" / "out.json");
  EXPECT_FALSE(fs::exists(dir / "missing"));
}

TEST_F(AtomicFileTest, CheckingAloneWritesNothing) {
  EXPECT_NO_THROW(checkOutputFile(dir / "out.json"));
  EXPECT_TRUE(entries().empty());
  fs::create_symlink("/etc/passwd", dir / "link");
  EXPECT_THROW(checkOutputFile(dir / "link"), OutputError);
}

TEST(WriteAll, ReportsAFullDevice) {
  const int fd = ::open("/dev/full", O_WRONLY);
  ASSERT_GE(fd, 0);
  errno = 0;
  EXPECT_FALSE(writeAll(fd, std::string(100000, 'x')));
  EXPECT_EQ(errno, ENOSPC);
  ::close(fd);
}

TEST_F(AtomicFileTest, AFullDiskFailsAndLeavesNeitherTargetNorTemporary) {
  const fs::path mount = dir / "small";
  fs::create_directory(mount);
  if (::mount("tmpfs", mount.c_str(), "tmpfs", 0, "size=64k") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << "); WriteAll.ReportsAFullDevice covers "
                 << "the write path";
  struct Unmount {
    fs::path path;
    ~Unmount() { ::umount(path.c_str()); }
  } unmount{mount};
  std::ofstream(mount / "out.json") << "old";
  try {
    writeFileAtomically(mount / "out.json", std::string(1 << 20, 'x'));
    ADD_FAILURE() << "1 MiB fitted in a 64 KiB file system";
  } catch (const OutputError& e) {
    EXPECT_FALSE(e.badTarget()) << e.what();
    EXPECT_NE(std::string(e.what()).find("No space left"), std::string::npos) << e.what();
  }
  EXPECT_EQ(slurp(mount / "out.json"), "old") << "the old contents stay whole";
  EXPECT_EQ(std::distance(fs::directory_iterator(mount), fs::directory_iterator()), 1) << "no temporary left";
}

// A drape killed with SIGKILL leaves its temporary; the next write into that folder removes it, and only
// what is certainly a stale one of ours: our name, a regular file, unlocked, untouched for a minute.
TEST_F(AtomicFileTest, StaleTemporariesOfOursAreRemovedByTheNextWriteThere) {
  const fs::path here = dir / "stale";  // a folder of its own: each folder is swept once per process
  fs::create_directories(here);
  const auto make = [&](const std::string& name, bool old) {
    std::ofstream(here / name) << "left";
    if (old) fs::last_write_time(here / name, fs::file_time_type::clock::now() - std::chrono::minutes(2));
  };
  make(".drape-Ab3dE9", true);      // a killed atomic write
  make(".drape-k9VIDx.mp4", true);  // a killed video
  make(".drape-fresh1", false);     // just made: its maker may not have locked it yet
  make(".drape-locked", true);      // in use: locked below
  make(".drape-short", true);       // not our pattern (5 characters)
  make("x.drape-Ab3dE9", true);
  make(".drape-Ab3dE9.m p4", true);
  fs::create_symlink("/etc/passwd", here / ".drape-link12");
  const int held = ::open((here / ".drape-locked").c_str(), O_RDONLY);
  ASSERT_GE(held, 0);
  ASSERT_EQ(::flock(held, LOCK_EX), 0);
  writeFileAtomically(here / "out.json", "new");
  ::close(held);
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(here))
    left.push_back(e.path().filename().string());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{".drape-Ab3dE9.m p4", ".drape-fresh1", ".drape-link12", ".drape-locked",
                                            ".drape-short", "out.json", "x.drape-Ab3dE9"}));
  EXPECT_TRUE(fs::exists("/etc/passwd"));
}

TEST_F(AtomicFileTest, ATemporaryIsLockedWhileInUseAndGoneAfter) {
  std::string name;
  {
    const TemporaryFile temporary(dir / "video.mp4", ".mp4");
    name = temporary.path();
    EXPECT_EQ(fs::path(name).parent_path(), dir);
    EXPECT_EQ(fs::path(name).extension(), ".mp4");
    EXPECT_EQ(fs::path(name).filename().string().rfind(".drape-", 0), 0u) << name;
    const int other = ::open(name.c_str(), O_RDONLY);
    ASSERT_GE(other, 0);
    EXPECT_EQ(::flock(other, LOCK_EX | LOCK_NB), -1) << "locked by its maker";
    ::close(other);
    EXPECT_TRUE(temporary.stillOurs());
  }
  EXPECT_FALSE(fs::exists(name)) << "removed when not renamed";
}

TEST_F(AtomicFileTest, ATemporaryReplacedByALinkIsNotOursAnyMore) {
  const TemporaryFile temporary(dir / "video.mp4", ".mp4");
  fs::remove(temporary.path());
  fs::create_symlink("/etc/passwd", temporary.path());
  EXPECT_FALSE(temporary.stillOurs());
}

TEST_F(AtomicFileTest, AReadOnlyFolderIsABadTargetBeforeAnyWrite) {
  const fs::path mount = dir / "readonly";
  fs::create_directory(mount);
  if (::mount("tmpfs", mount.c_str(), "tmpfs", MS_RDONLY, "size=64k") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << ")";
  struct Unmount {
    fs::path path;
    ~Unmount() { ::umount(path.c_str()); }
  } unmount{mount};
  try {
    const TemporaryFile temporary(mount / "video.mp4", ".mp4");
    ADD_FAILURE() << "made a file on a read-only file system";
  } catch (const OutputError& e) {
    EXPECT_TRUE(e.badTarget()) << e.what();
    EXPECT_NE(std::string(e.what()).find("Read-only file system"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace drape
