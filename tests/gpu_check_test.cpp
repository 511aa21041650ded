// tools/gpu-check without a build or a GPU: its usage, the pack layout it insists on, and the run's
// failure with nothing to run (a summary still written). The real check is the script run end to end
// (docs/gpu-machine.md); these keep its contract from drifting.
#include "shell_quote.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using drape::testing::quote;

struct Result {
  int status = -1;
  std::string out;  // stdout and stderr
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class GpuCheck : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("drape_gpu_check_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The script from the source folder, as a user runs it; `environment` goes before it.
  Result run(const std::string& args, const std::string& environment = "") const {
    const fs::path out = dir_ / "output";
    const std::string script = std::string(drape::test::sourceDir()) + "/tools/gpu-check";
    const std::string cmd =
        environment + " " + quote(script) + " " + args + " >" + quote(out.string()) + " 2>&1 </dev/null";
    const int raw = std::system(cmd.c_str());
    return {WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw), slurp(out)};
  }

  // A pack with every file the run needs, as empty stand-ins: enough for the layout check.
  fs::path fakePack() const {
    const fs::path pack = dir_ / "pack with space";
    fs::create_directories(pack / "bin");
    fs::create_directories(pack / "lib" / "compat");
    for (const char* name : {"drape", "gpu_passes_gl_test", "gpu_runs_gl_test", "gpu_determinism_gl_test",
                             "gpu_grid_gl_test", "gpu_mesh_gl_test", "gpu_xpbd_gl_test", "gpu_tethers_gl_test",
                             "gpu_solver_gl_test", "gpu_variants_gl_test"}) {
      std::ofstream(pack / "bin" / name) << "#!/bin/sh\n";
      fs::permissions(pack / "bin" / name, fs::perms::owner_all);
    }
    for (const char* name :
         {"libEGL.so.1", "libGLdispatch.so.0", "libOpenGL.so.0", "libGLX.so.0", "libGL.so.1", "libfmt.so.9"})
      std::ofstream(pack / "lib" / name) << "stand-in";
    std::ofstream(pack / "lib" / "compat" / "libstdc++.so.6") << "stand-in";
    std::ofstream(pack / "MANIFEST") << "source_dir=/nowhere\ncommit=abc1234\n";
    return pack;
  }

  fs::path dir_;
};

TEST_F(GpuCheck, HelpNamesBothHalvesAndWhereResultsGo) {
  const Result r = run("--help");
  EXPECT_EQ(r.status, 0) << r.out;
  for (const char* word : {"--pack", "--smoke", "--check-pack", "$OUT", "summary.md", ".gpu"})
    EXPECT_NE(r.out.find(word), std::string::npos) << "--help mentions " << word << ":\n" << r.out;
}

TEST_F(GpuCheck, AnUnknownOptionIsRefused) {
  const Result r = run("--frobnicate");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("unknown option '--frobnicate'"), std::string::npos) << r.out;
}

TEST_F(GpuCheck, ACompletePackPassesTheLayoutCheck) {
  const Result r = run("--check-pack " + quote(fakePack().string()));
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("10 binaries"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("abc1234"), std::string::npos) << "names the commit it was built from: " << r.out;
}

TEST_F(GpuCheck, APackCarryingGlibcADriverOrAMisplacedRuntimeIsRefusedWithEachProblem) {
  const fs::path pack = fakePack();
  fs::remove(pack / "bin" / "gpu_runs_gl_test");
  fs::remove(pack / "lib" / "libOpenGL.so.0");
  for (const char* name : {"libc.so.6", "libEGL_mesa.so.0", "libgallium-0.so", "libgomp.so.1"})
    std::ofstream(pack / "lib" / name) << "stand-in";
  const Result r = run("--check-pack " + quote(pack.string()));
  EXPECT_EQ(r.status, 1) << r.out;
  for (const char* problem : {"bin/gpu_runs_gl_test is missing", "lib/libOpenGL.so.0 is missing", "libc.so.6 is glibc",
                              "libEGL_mesa.so.0 is a GL driver library", "libgallium-0.so is a GL driver library",
                              "libgomp.so.1 belongs in lib/compat", "6 problems"})
    EXPECT_NE(r.out.find(problem), std::string::npos) << "expected '" << problem << "' in:\n" << r.out;
}

TEST_F(GpuCheck, PackNeverReplacesAFolderThatIsNotAPack) {
  // Checked before the build: a mistyped --pack . or --pack docs must not cost the folder.
  const fs::path folder = dir_ / "notes";
  fs::create_directories(folder);
  std::ofstream(folder / "keep.txt") << "mine";
  const Result r = run("--pack " + quote(folder.string()));
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("is not a pack"), std::string::npos) << r.out;
  EXPECT_EQ(slurp(folder / "keep.txt"), "mine");
}

TEST_F(GpuCheck, TheRunWithoutAPackStopsAtOnceAndStillWritesTheSummary) {
  const fs::path out = dir_ / "results";
  const Result r = run(quote(out.string()), "DRAPE_GPU_PACK=" + quote((dir_ / "absent").string()));
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("no pack"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("tools/gpu-check --pack"), std::string::npos) << "says how to make one: " << r.out;
  const std::string summary = slurp(out / "summary.md");
  EXPECT_NE(summary.find("**stopped: no pack"), std::string::npos) << summary;
  EXPECT_TRUE(fs::exists(out / "log.txt"));
  int files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(out))
    ++files;
  EXPECT_LE(files, 8) << "the GPU machine returns 8 files at most";
}

}  // namespace
