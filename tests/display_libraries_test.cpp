// GLFW and EGL are opened when a command makes a GL context, not when drape starts (gl/display_libraries.hpp).
#include "gl/display_libraries.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

namespace drape {
namespace {

// What the dynamic loader says it loaded for `command` (glibc's LD_DEBUG=files, on standard error)
std::string loadedFiles(const std::string& command) {
  std::string out;
  FILE* pipe = ::popen(("LD_DEBUG=files " + command + " 2>&1 >/dev/null").c_str(), "r");
  if (pipe == nullptr) return out;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr)
    out += buffer;
  ::pclose(pipe);
  return out;
}

TEST(DisplayLibraries, ACommandWithoutAContextLoadsNeither) {
  const std::string files = loadedFiles(std::string(test::drapeBinary()) + " simulate " + test::sourceDir() +
                                        "/scenes/pinned2.json --frames 1 --solver cpu");
  ASSERT_NE(files.find("file=libgomp.so.1"), std::string::npos) << "no LD_DEBUG output to judge:\n" << files;
  EXPECT_EQ(files.find("libglfw"), std::string::npos) << files;
  EXPECT_EQ(files.find("libEGL"), std::string::npos) << files;
  EXPECT_EQ(files.find("libX11"), std::string::npos) << files;
}

TEST(DisplayLibraries, OpeningOneMapsItOnce) {
  const std::string error = gl::openDisplayLibrary(gl::DisplayLibrary::Egl);
  if (!error.empty()) GTEST_SKIP() << error;
  EXPECT_EQ(gl::openDisplayLibrary(gl::DisplayLibrary::Egl), "");
  std::ifstream maps("/proc/self/maps");
  std::stringstream text;
  text << maps.rdbuf();
  EXPECT_NE(text.str().find("libEGL.so.1"), std::string::npos);
}

TEST(DisplayLibraries, AMissingLibraryIsNamedWithItsPackage) {
  void* handle = reinterpret_cast<void*>(1);
  const std::string error = gl::detail::openLibrary("libdrape-no-such-library.so.9", "drape-nothing", handle);
  EXPECT_EQ(handle, nullptr);
  EXPECT_NE(error.find("cannot open libdrape-no-such-library.so.9"), std::string::npos) << error;
  EXPECT_NE(error.find("drape-nothing"), std::string::npos) << error;
}

}  // namespace
}  // namespace drape
