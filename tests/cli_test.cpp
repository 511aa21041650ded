// The `drape` command line as a user meets it: runs the real binary as a subprocess.
#include "app/stability_cases.hpp"
#include "test_paths.hpp"

#include "shell_quote.hpp"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

extern char** environ;

namespace {

namespace fs = std::filesystem;

struct Result {
  int status = -1;
  std::string out, err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const fs::path& tempDir() {
  static const drape::test::TempDir dir("drape_cli_test_");
  return dir.path();
}

// `prefix` goes before the binary: a `cd`, environment settings, `timeout`.
Result run(const std::string& args, const std::string& prefix = "") {
  const fs::path dir = tempDir();
  const std::string cmd = prefix + " " + std::string(drape::test::drapeBinary()) + " " + args + " >" +
                          (dir / "out").string() + " 2>" + (dir / "err").string() + " </dev/null";
  int raw = std::system(cmd.c_str());
  Result r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  r.out = slurp(dir / "out");
  r.err = slurp(dir / "err");
  return r;
}

std::string scene(const std::string& name) {
  return std::string(drape::test::sourceDir()) + "/scenes/" + name;
}

fs::path writeScene(const std::string& name, const std::string& json) {
  fs::path p = tempDir() / name;
  std::ofstream(p) << json;
  return p;
}

const char* kCloth = R"("cloth": {"width": 1, "height": 1, "num_width_points": 8, "num_height_points": 8,
  "thickness": 0.01, "orientation": 0)";

struct BadCase {
  const char* name;
  std::string json;    // scene file contents ("" means: do not create the file)
  std::string args;    // extra arguments
  std::string expect;  // substring the error line must contain (key and problem)
};

class BadInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadInput, OneLineStatusTwoAndNoOutputFile) {
  const BadCase& c = GetParam();
  const std::string file = std::string(c.name) + ".json";
  fs::path path = tempDir() / file;
  fs::remove(path);
  if (!c.json.empty()) path = writeScene(file, c.json);
  const fs::path out = tempDir() / (std::string(c.name) + "_out.json");
  fs::remove(out);
  Result r = run("simulate " + path.string() + " --frames 1 --out " + out.string() + " " + c.args);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "exactly one line: " << r.err;
  EXPECT_NE(r.err.find(c.expect), std::string::npos) << "expected '" << c.expect << "' in: " << r.err;
  if (c.args.empty()) {
    EXPECT_NE(r.err.find(file), std::string::npos) << "the message names the file: " << r.err;
  }
  EXPECT_FALSE(fs::exists(out)) << "no output on failure";
  EXPECT_FALSE(fs::exists(out.string() + ".partial"));
}

std::string cloth(const std::string& extra) {
  return "{" + std::string(kCloth) + extra + "}}";
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadInput,
    ::testing::Values(
        BadCase{"missing_file", "", "", "cannot"},
        BadCase{"invalid_json", "{\n \"cloth\": {\n  \"width\": 1,,\n}", "", "line 3"},
        BadCase{"unknown_key", cloth(R"(, "colour": 3)"), "", "cloth.colour"},
        BadCase{"wrong_type", cloth(R"(, "ks": "stiff")"), "", "cloth.ks"},
        BadCase{"missing_required", R"({"cloth": {"width": 1}})", "", "cloth.height"},
        BadCase{"too_few_points",
                R"({"cloth": {"width": 1, "height": 1, "num_width_points": 1, "num_height_points": 8,
                   "thickness": 0.01, "orientation": 0}})",
                "", "cloth.num_width_points"},
        BadCase{"too_large",
                R"({"cloth": {"width": 1, "height": 1, "num_width_points": 100000, "num_height_points": 100000,
                   "thickness": 0.01, "orientation": 0}})",
                "", "grid too large"},
        BadCase{"negative_density", cloth(R"(, "density": -1)"), "", "cloth.density"},
        BadCase{"zero_ks", cloth(R"(, "ks": 0)"), "", "cloth.ks"},
        BadCase{"damping_range", cloth(R"(, "damping": 150)"), "", "cloth.damping"},
        BadCase{"friction_range", cloth(R"(}, "sphere": {"origin": [0,0,0], "radius": 0.2, "friction": 2)"), "",
                "sphere.friction"},
        BadCase{"pinned_outside", cloth(R"(, "pinned": [[0, 0], [8, 0]])"), "", "cloth.pinned"},
        BadCase{"zero_normal", cloth(R"(}, "plane": {"point": [0,0,0], "normal": [0,0,0], "friction": 0.5)"), "",
                "plane.normal"},
        BadCase{"non_finite", cloth(R"(, "ks": 1e999)"), "", "cloth.ks"},
        BadCase{"negative_frames", cloth(""), "--frames -3", "--frames"},
        // Values that vanish or overflow in float, and counts that would run forever.
        BadCase{"thickness_vanishes",
                R"({"cloth": {"width": 1, "height": 1, "num_width_points": 8, "num_height_points": 8,
                   "thickness": 1e-300, "orientation": 0}})",
                "", "cloth.thickness"},
        BadCase{"noise_scale_vanishes", cloth(R"(}, "simulation": {"wind": {"noise_scale": 1e-300})"), "",
                "simulation.wind.noise_scale"},
        BadCase{"ks_beyond_float", cloth(R"(, "ks": 1e300)"), "", "cloth.ks"},
        BadCase{"endless_steps", cloth(R"(}, "simulation": {"steps_per_frame": 2000000000)"), "",
                "simulation.steps_per_frame: must be <= 10000"},
        BadCase{"endless_stretch_passes", cloth(R"(}, "simulation": {"stretch_passes": 2000000000)"), "",
                "simulation.stretch_passes: must be <= 100"},
        BadCase{"time_step_vanishes", cloth(R"(}, "simulation": {"frames_per_sec": 1e38, "steps_per_frame": 100)"), "",
                "simulation.frames_per_sec"},
        BadCase{"unknown_solver", cloth(""), "--solver quantum", "--solver"}),
    [](const auto& row) { return std::string(row.param.name); });

TEST(Cli, SimulatePrintsTheSummary) {
  Result r = run("simulate " + scene("pinned2.json") + " --frames 9");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* field : {"frames", "simulated", "y range", "centroid", "max strain", "ms per frame"})
    EXPECT_NE(r.out.find(field), std::string::npos) << field << " missing from:\n" << r.out;
}

// --waits: where a team waited, by line, after the summary; one thread has none to show; the GPU solvers have no team
TEST(Cli, SimulateWaitsListsTheTeamsWaits) {
  Result r = run("simulate " + scene("selfCollision.json") + " --frames 1 --threads 2 --team always --waits");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("waits        a team of 2 ran 30 substeps"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cpu/cpu_solver_self_collision.cpp:"), std::string::npos) << r.out;
  r = run("simulate " + scene("selfCollision.json") + " --frames 1 --threads 1 --waits");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("waits        none: no substep ran on a team"), std::string::npos) << r.out;
  r = run("simulate " + scene("selfCollision.json") + " --frames 1 --solver gpu --waits");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--waits: the CPU solvers only"), std::string::npos) << r.err;
}

TEST(Cli, SameCommandSameOutputByteForByte) {
  const fs::path a = tempDir() / "a.json", b = tempDir() / "b.json";
  for (const fs::path& p : {a, b}) {
    Result r = run("simulate " + scene("selfCollision.json") + " --frames 5 --out " + p.string());
    ASSERT_EQ(r.status, 0) << r.err;
  }
  const std::string ja = slurp(a);
  EXPECT_GT(ja.size(), 2500u * 10);
  EXPECT_EQ(ja, slurp(b));
}

TEST(Cli, SummaryReportsTheColliders) {
  Result r = run("simulate " + scene("sphere.json") + " --frames 3 --solver cpu64");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("sphere 0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cpu64"), std::string::npos) << r.out;
}

// `penetration` reads what `simulate --export` wrote: a cloth square 2 cm under the top of a 1 m box is 20 mm
// inside from frame 0 (the export of the state before any step); a file that is not this cloth is refused.
TEST(Cli, PenetrationMeasuresExportedFrames) {
  const fs::path dir = tempDir() / "penetration";
  fs::create_directories(dir);
  std::ofstream(dir / "box.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
                                    "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  std::ofstream(dir / "square.obj") << "v 0.4 0.98 0.4\nv 0.6 0.98 0.4\nv 0.6 0.98 0.6\nv 0.4 0.98 0.6\nf 1 4 3 2\n";
  const fs::path scene_file = writeScene("penetration/scene.json", R"({"cloth": {"mesh": "square.obj",
      "thickness": 0.005}, "meshes": [{"obj": "box.obj"}]})");
  Result r = run("simulate " + scene_file.string() + " --frames 0 --export " + (dir / "cloth.obj").string());
  ASSERT_EQ(r.status, 0) << r.err;
  r = run("penetration " + scene_file.string() + " " + (dir / "cloth_0000.obj").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("contact      from frame 0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("vertex       deepest 20.000 mm (frame 0,"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(": 20.000 mm, 4 points inside"), std::string::npos) << r.out;
  r = run("penetration " + scene_file.string() + " " + (dir / "box.obj").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("box.obj: 8 vertices, but the cloth of"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  r = run("penetration " + scene("pinned2.json") + " " + (dir / "cloth_0000.obj").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("no sphere or mesh obstacle"), std::string::npos) << r.err;
}

// A cloth finer than its thickness: simulate names the scene and the pairs self-collision skips; CS184's
// 50 x 50 file gets no such line.
TEST(Cli, SimulateWarnsWherePairsAreHeldAtRest) {
  const fs::path fine = writeScene("fine.json", R"({"cloth": {"width": 1, "height": 1, "num_width_points": 80,
      "num_height_points": 80, "thickness": 0.0095, "orientation": 0, "pinned": [[0, 0], [79, 0]]}})");
  Result r = run("simulate " + fine.string() + " --frames 1");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("fine.json: cloth.thickness: 2 x thickness (19 mm) is more than the rest distance of"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("self-collision skips them"), std::string::npos) << r.err;
  r = run("simulate " + scene("selfCollision.json") + " --frames 1");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("self-collision skips"), std::string::npos) << r.err;
}

// The files come before the summary: a summary that cannot be written (stdout on a full disk) is an error
// that costs nothing already computed.
TEST(Cli, TheOutputIsWrittenBeforeTheSummary) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const fs::path out = tempDir() / "before_summary.json", err = tempDir() / "before_summary.err";
  fs::remove(out);
  const std::string command = std::string(drape::test::drapeBinary()) + " simulate " + scene("pinned2.json") +
                              " --frames 1 --out " + out.string() + " >/dev/full 2>" + err.string() + " </dev/null";
  const int raw = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(raw));
  EXPECT_EQ(WEXITSTATUS(raw), 1) << slurp(err);
  EXPECT_EQ(slurp(err), "drape: simulate: cannot write the summary to standard output: No space left on device\n");
  EXPECT_EQ(slurp(out).substr(0, 2), "[\n") << "the positions were written";
}

// ks = 1e7 N/m at one substep per frame: dt sqrt(k_sum / m) = (1/90) sqrt(8.8e7 / 2.34) = 68, far
// beyond the stability bound of about 1.4. Pinned at a corner, so the springs stretch from the first
// step. The run must stop with status 4 and one line, and write no output; the same scene with
// --auto-substeps runs inside the bound and succeeds, so the failure is the blow-up and not the file.
TEST(Cli, ABlowUpExitsWithStatusFourAndWritesNothing) {
  const fs::path path = writeScene("blows_up.json", "{" + std::string(kCloth) + R"(, "ks": 1e7, "pinned": [[0, 0]]},
    "simulation": {"steps_per_frame": 1, "stretch_passes": 0, "self_collision": false}})");
  const fs::path out = tempDir() / "blows_up_out.json";
  fs::remove(out);
  Result r = run("simulate " + path.string() + " --frames 30 --out " + out.string());
  EXPECT_EQ(r.status, 4) << r.out << r.err;
  EXPECT_NE(r.err.find("blew up at frame"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out)) << "no output from a blown-up run";

  Result guarded = run("simulate " + path.string() + " --frames 30 --auto-substeps --out " + out.string());
  EXPECT_EQ(guarded.status, 0) << guarded.err;
  EXPECT_TRUE(fs::exists(out));
}

// ---------------------------------------------------------------------------------------------------
// Hostile names and output paths.

using drape::testing::kHostile;
using drape::testing::quote;

fs::path freshDir(const std::string& name) {
  const fs::path dir = tempDir() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// 6 x 6 points without self-collision: an accuracy run of it takes a moment.
const char* kTinyScene = R"({"cloth": {"width": 1, "height": 1, "num_width_points": 6, "num_height_points": 6,
  "thickness": 0.01, "orientation": 1, "pinned": [[0, 5], [5, 5]]}, "simulation": {"self_collision": false}})";

const char* kTinyAccuracy = " --solver cpu --steps 2 --passes 1 --times 0.05 --reference-factor 2";

TEST(ChildProcesses, ThePlotGetsHostileNamesAsArgumentsNotAsCommands) {
  const fs::path dir = freshDir("inject_plot");
  const fs::path scene_file = dir / (kHostile + ".json"), out = dir / ("o" + kHostile);
  std::ofstream(scene_file) << kTinyScene;
  // Stands in for python: answers the matplotlib probe, records the plot's arguments one per line, and
  // draws a "picture" where it is told to.
  const fs::path python = dir / "python";
  std::ofstream(python) << "#!/bin/sh\n[ \"$1\" = -c ] && exit 0\nfor a in \"$@\"; do printf '%s\\n' \"$a\"; done > "
                        << quote((dir / "args").string()) << "\nprintf picture > \"$4\"\n";
  fs::permissions(python, fs::perms::owner_all);
  const Result r = run("accuracy " + quote(scene_file.string()) + " --out " + quote(out.string()) + kTinyAccuracy,
                       "cd " + quote(dir.string()) + " && DRAPE_PYTHON=" + quote(python.string()));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir / "PWNED")) << "a name ran a command";
  const std::string args = slurp(dir / "args");
  EXPECT_NE(args.find("\n--title=" + kHostile + "\n"), std::string::npos) << args;
  EXPECT_NE(args.find("\n" + (out / "accuracy.csv").string() + "\n"), std::string::npos) << args;
  // The picture went to a temporary of drape's beside accuracy.png, then was renamed over it.
  EXPECT_EQ(args.find("\n" + (out / "accuracy.png").string() + "\n"), std::string::npos) << args;
  EXPECT_NE(args.find("\n" + (out / ".drape-").string()), std::string::npos) << args;
  EXPECT_EQ(slurp(out / "accuracy.png"), "picture");
  for (const fs::directory_entry& e : fs::directory_iterator(out))
    EXPECT_EQ(e.path().filename().string().find(".drape-"), std::string::npos) << "left behind: " << e.path();
}

TEST(ChildProcesses, TheRealPlotWritesItsPictureForAHostileName) {
  if (std::system("/usr/bin/python3 -c 'import matplotlib' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "no matplotlib for /usr/bin/python3 (tools/setup installs python3-matplotlib)";
  const fs::path dir = freshDir("inject_real_plot");
  const fs::path scene_file = dir / (kHostile + ".json"), out = dir / ("o" + kHostile);
  std::ofstream(scene_file) << kTinyScene;
  const Result r = run("accuracy " + quote(scene_file.string()) + " --out " + quote(out.string()) + kTinyAccuracy,
                       "cd " + quote(dir.string()) + " && env -u DRAPE_PYTHON");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir / "PWNED")) << "a name ran a command";
  EXPECT_TRUE(fs::exists(out / "accuracy.png")) << r.err;
}

class SimulateOut : public ::testing::Test {
 protected:
  fs::path dir = freshDir("simulate_out");
  Result simulate(const fs::path& out, const std::string& prefix = "") {
    return run("simulate " + scene("pinned2.json") + " --frames 2 --out " + quote(out.string()), prefix);
  }
  void expectRefused(const Result& r, const fs::path& out) {
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find(out.string()), std::string::npos) << "names the path: " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(r.out.empty()) << "the path is checked before the run: " << r.out;
  }
};

TEST_F(SimulateOut, ASymbolicLinkIsRefusedAndWhatItPointsToKept) {
  std::ofstream(dir / "victim") << "precious";
  fs::create_symlink(dir / "victim", dir / "out.json");
  expectRefused(simulate(dir / "out.json"), dir / "out.json");
  EXPECT_EQ(slurp(dir / "victim"), "precious");
}

TEST_F(SimulateOut, ALinkPlantedAtTheTemporaryNameIsNotWrittenThrough) {
  std::ofstream(dir / "victim") << "precious";
  fs::create_symlink(dir / "victim", dir / "out.json.partial");
  const Result r = simulate(dir / "out.json");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(slurp(dir / "victim"), "precious");
  EXPECT_EQ(slurp(dir / "out.json").substr(0, 2), "[\n");
}

TEST_F(SimulateOut, AFifoIsRefusedWithoutWaitingForAReader) {
  ASSERT_EQ(::mkfifo((dir / "out.json").c_str(), 0600), 0);
  expectRefused(simulate(dir / "out.json", "timeout 60"), dir / "out.json");
  EXPECT_TRUE(fs::is_fifo(dir / "out.json"));
}

TEST_F(SimulateOut, ADeviceIsRefusedAndStaysADevice) {
  // A node of /dev/full's device in the test's directory: a failing run replaces this one, not the machine's.
  const fs::path device = dir / "full";
  if (::mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 7)) != 0) GTEST_SKIP() << "mknod: " << std::strerror(errno);
  expectRefused(simulate(device), device);
  EXPECT_TRUE(fs::is_character_file(device));
}

TEST_F(SimulateOut, ADirectoryOrAMissingDirectoryIsStatusTwo) {
  fs::create_directory(dir / "out.json");
  expectRefused(simulate(dir / "out.json"), dir / "out.json");
  expectRefused(simulate(dir / "missing" / "out.json"), dir / "missing" / "out.json");
}

TEST_F(SimulateOut, AFullDiskIsStatusOneAndLeavesNoFile) {
  const fs::path mount = dir / "small";
  fs::create_directory(mount);
  if (std::system(("mount -t tmpfs -o size=16k tmpfs " + quote(mount.string()) + " 2>/dev/null").c_str()) != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here; AtomicFileTest and WriteAll cover the write errors";
  const Result r =
      run("simulate " + scene("selfCollision.json") + " --frames 1 --out " + quote((mount / "out.json").string()));
  const std::vector<fs::path> left(fs::directory_iterator(mount), fs::directory_iterator{});
  std::system(("umount " + quote(mount.string())).c_str());
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("No space left"), std::string::npos) << r.err;
  EXPECT_TRUE(left.empty()) << "left behind: " << (left.empty() ? "" : left.front().string());
}

// ---------------------------------------------------------------------------------------------------
// Limits.

// A bound on the drape process's memory. AddressSanitizer reserves terabytes of address space for its
// shadow at start, so under it a virtual-memory limit stops drape before main ("ReserveShadowMemoryRange
// failed"); there the timeout alone bounds the run.
#ifdef __SANITIZE_ADDRESS__
constexpr const char* kBoundedRun = "timeout 60";
#else
constexpr const char* kBoundedRun = "ulimit -v 4000000; timeout 60";
#endif

TEST(Limits, AnEndlessSceneFileIsRefusedUnread) {
  // Without the bound the old loader read /dev/zero until memory ran out; a device is not read at all.
  const Result r = run("simulate /dev/zero --frames 1", kBoundedRun);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("/dev/zero: cannot open: is a device, not a file"), std::string::npos) << r.err;
}

TEST(Limits, ASceneFileOverSixteenMebibytesIsRefused) {
  // Valid JSON: a cloth followed by 17 MiB of spaces.
  const fs::path file = writeScene("huge.json", cloth("") + std::string(17 << 20, ' '));
  const Result r = run("simulate " + file.string() + " --frames 1");
  fs::remove(file);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("too large for a scene"), std::string::npos) << r.err;
}

TEST(Limits, AccuracySampleTimesAreBounded) {
  const fs::path file = writeScene("tiny_accuracy.json", kTinyScene);
  for (const char* times : {"1e9", "601", "1e400"}) {
    const Result r = run("accuracy " + file.string() + " --no-plot --out " + (tempDir() / "acc").string() +
                         " --solver cpu --steps 2 --passes 1 --times " + times);
    EXPECT_EQ(r.status, 2) << times << ": " << r.err;
    EXPECT_NE(r.err.find("--times"), std::string::npos) << r.err;
  }
}

TEST(Limits, SubstepsPassesAndSizesOnTheCommandLineAreBounded) {
  const fs::path file = writeScene("tiny_limits.json", kTinyScene);
  const std::pair<std::string, std::string> cases[] = {
      {"stability --steps 1,20000 --out " + (tempDir() / "stab").string(), "--steps: 20000 is above the maximum 10000"},
      {"accuracy " + file.string() + " --steps 99999999999", "--steps"},
      {"accuracy " + file.string() + " --passes 1000", "--passes: 1000 is above the maximum 100"},
      {"bench --sizes 4096", "--sizes: 4096 is above the maximum 2048"},
      {"bench --solver cpu --sizes 4 --baseline /nonexistent/old.json",
       "--baseline: /nonexistent/old.json: cannot open: no such file"},
      {"bench --solver cpu --sizes 4 --baseline " + tempDir().string(),
       "--baseline: " + tempDir().string() + ": cannot open: is a directory, not a file"},
      {"bench --solver cpu --sizes 4 --baseline " + file.string(),
       "--baseline: " + file.string() + ": \"runs\": missing"},
  };
  for (const auto& [args, message] : cases) {
    const Result r = run(args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << ": " << r.err;
  }
}

// Hostile mesh files as a user meets them: status 2 and one line naming the scene, the key, the file and,
// where the problem is on a line, its number; nothing waits (a FIFO with no writer) or reads without end.
TEST(Limits, HostileMeshFilesAreOneLineEach) {
  const fs::path dir = freshDir("hostile_meshes");
  std::ofstream(dir / "tab_nan.obj") << "v 0 0 0\nv\tnan 0 0\nv 0 0 1\nf 1 2 3\n";
  std::ofstream(dir / "hex.obj") << "v 0x10 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n";
  std::ofstream(dir / "index.obj") << "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 99999999999\n";
  ASSERT_EQ(::mkfifo((dir / "fifo.obj").c_str(), 0600), 0);
  fs::create_symlink("loop.obj", dir / "loop.obj");
  const std::pair<std::string, std::string> cases[] = {
      {"tab_nan.obj", "tab_nan.obj: line 2: vertex coordinate 'nan' is not a finite number"},
      {"hex.obj", "hex.obj: line 1: vertex coordinate '0x10' is not a number"},
      {"index.obj", "index.obj: line 4: face corner '99999999999' names vertex 99999999999, but only 3 come"},
      {"fifo.obj", "fifo.obj: cannot read: a FIFO with nothing written to it"},
      {"loop.obj", "loop.obj: cannot open: Too many levels of symbolic links"},
      {"/dev/zero", "/dev/zero: cannot open: is a device, not a file"}};
  for (const auto& [obj, message] : cases) {
    const fs::path file = dir / "scene.json";
    std::ofstream(file) << "{" << kCloth << R"(}, "meshes": [{"obj": ")" << obj << R"("}]})";
    const Result r = run("simulate " + file.string() + " --frames 1", "timeout 60");
    EXPECT_EQ(r.status, 2) << obj << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(file.string() + ": meshes[0].obj: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  }
}

TEST(Limits, ABaselineThatIsAFifoWithNoWriterIsRefusedAtOnce) {
  const fs::path fifo = freshDir("fifo_baseline") / "old.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const Result r = run("bench --solver cpu --sizes 4 --baseline " + fifo.string(), "timeout 60");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("--baseline: " + fifo.string() + ": cannot read: a FIFO with nothing written to it"),
            std::string::npos)
      << r.err;
}

// Out of memory is one line naming what was being allocated, and the limit when there is one. A 2048^2
// cloth in 300 MB of address space: the solver's buffers do not fit. AddressSanitizer cannot start in so
// little (its shadow), so there the case is not run.
TEST(Limits, OutOfMemoryIsOneLineNamingWhatWasBeingAllocated) {
#ifdef __SANITIZE_ADDRESS__
  GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space; a limit stops it before main";
#endif
  const fs::path file = writeScene("out_of_memory.json", R"({"cloth": {"width": 1, "height": 1,
    "num_width_points": 2048, "num_height_points": 2048, "thickness": 0.0002, "orientation": 0},
    "simulation": {"self_collision": false, "integrator": "xpbd"}})");
  const Result r = run("simulate " + file.string() + " --frames 1", "ulimit -v 300000;");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(r.err,
            "drape: out of memory while building the cpu solver for 4194304 points (this process may use "
            "300000 KiB: ulimit -v)\n");
}

// ---------------------------------------------------------------------------------------------------
// Exit statuses and messages, as docs/exit-status.md lists them.

TEST(ExitStatus, AnUnknownSubcommandIsStatusTwoAndNamed) {
  Result r = run("frobnicate");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("frobnicate"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("simulate"), std::string::npos) << "lists the commands: " << r.err;
  r = run("--threads 2");  // options but no command
  EXPECT_EQ(r.status, 2) << r.err;
}

bool hasLongNumber(const std::string& text) {
  // DBL_MAX written out, or in any form: no option's range needs 20 digits or e+308.
  int run_length = 0;
  for (char c : text) {
    run_length = std::isdigit(static_cast<unsigned char>(c)) ? run_length + 1 : 0;
    if (run_length >= 20) return true;
  }
  return text.find("e+308") != std::string::npos || text.find("1.79769") != std::string::npos;
}

TEST(ExitStatus, HelpIsStatusZeroAndShowsNoDoubleMaximum) {
  for (const char* command : {"", "simulate", "view", "render", "bench", "accuracy", "stability", "penetration"}) {
    const Result r = run(std::string(command) + " --help");
    EXPECT_EQ(r.status, 0) << command << ": " << r.err;
    EXPECT_FALSE(hasLongNumber(r.out)) << command << " --help:\n" << r.out;
  }
}

// Every option's default is in --help: `render` writes 91 images unless told otherwise, and says so.
TEST(ExitStatus, HelpShowsTheDefaults) {
  const Result render = run("render --help");
  EXPECT_NE(render.out.find("--frames INT:INT in [0 - 1000000]=90"), std::string::npos) << render.out;
  EXPECT_NE(render.out.find("--every INT:INT in [1 - 1000000]=1"), std::string::npos) << render.out;
  EXPECT_NE(render.out.find("--size TEXT=640x480"), std::string::npos) << render.out;
  const Result simulate = run("simulate --help");
  EXPECT_NE(simulate.out.find("--frames INT:>= 0=90"), std::string::npos) << simulate.out;
  EXPECT_NE(simulate.out.find("=cpu"), std::string::npos) << simulate.out;
}

// A slip in an option's or a command's name gets the nearest one it may have been, on the one line.
TEST(ExitStatus, AnUnknownOptionOrCommandSuggestsTheNearest) {
  const std::string s = scene("pinned2.json");
  const std::pair<std::string, std::string> cases[] = {
      {"simulate " + s + " --frame 3", "simulate: unknown option --frame (did you mean --frames?)"},
      {"--verison", "unknown option --verison (did you mean --version?)"},
      {"simulat " + s, "unknown command 'simulat' (did you mean simulate?"},
      {"render " + s + " --out o --evry 2", "render: unknown option --evry (did you mean --every?)"},
      {"bench --sizes 32 --jbos 2", "bench: unknown option --jbos"},
      {"stability --zzz", "stability: unknown option --zzz (drape stability --help)"},
  };
  for (const auto& [args, message] : cases) {
    const Result r = run(args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << ": " << r.err;
  }
}

TEST(ExitStatus, BadOptionValuesAreStatusTwoWithOneShortLine) {
  const std::string s = scene("pinned2.json");
  const std::string cases[] = {
      "simulate " + s + " --frames -1",
      "simulate " + s + " --frames 1 --frames 2",
      "simulate " + s + " " + s,
      "render " + s + " --out o --frames -1",
      "render " + s + " --out o --every 0",
      "render " + s + " --out o --samples 0",
      "render " + s + " --out o --samples 17",
      "render " + s + " --out o --zoom 0",
      "view " + s + " --frames 0",
      "bench --frames 0",
      "bench --warmup -1",
      "bench --repeats 0",
      "bench --budget 0",
      "bench --budget -5",
      "accuracy " + s + " --reference-factor 1",
      "simulate " + s + " --integrator rk4",
      "render " + s + " --out o --integrator XPBD",
      "view " + s + " --integrator",
      "bench --integrator implicit",
      "accuracy " + s + " --integrator verlet,rk4",
      "stability --integrator both",
      "stability --xpbd-steps 0",
      "stability --implicit-steps 1,x",
  };
  for (const std::string& args : cases) {
    const Result r = run(args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
    EXPECT_FALSE(hasLongNumber(r.err)) << args << ": " << r.err;
    EXPECT_EQ(r.err.find("At Most"), std::string::npos) << args << ": " << r.err;
    EXPECT_LT(r.err.size(), 200u) << args << ": " << r.err;
  }
}

// --integrator replaces the scene's integrator: the same scene falls differently, and the key in a scene
// file does what the option does.
TEST(Cli, TheIntegratorOptionRunsXpbdAsTheSceneKeyDoes) {
  const std::string s = scene("pinned2.json");
  const Result verlet = run("simulate " + s + " --frames 5 --threads 1");
  const Result xpbd = run("simulate " + s + " --frames 5 --threads 1 --integrator xpbd");
  ASSERT_EQ(verlet.status, 0) << verlet.err;
  ASSERT_EQ(xpbd.status, 0) << xpbd.err;
  const auto centroid = [](const std::string& out) { return out.substr(out.find("centroid"), 50); };
  EXPECT_NE(centroid(verlet.out), centroid(xpbd.out));
  const fs::path file = writeScene("xpbd_key.json", R"({"cloth": {"damping": 0.2, "density": 150.0, "ks": 5000.0,
    "orientation": 0, "width": 1, "height": 1, "num_width_points": 50, "num_height_points": 50, "thickness": 0.0095,
    "pinned": [[0, 0], [49, 0]]}, "simulation": {"self_collision": false, "integrator": "xpbd"}})");
  const Result keyed = run("simulate " + file.string() + " --frames 5 --threads 1");
  ASSERT_EQ(keyed.status, 0) << keyed.err;
  EXPECT_EQ(centroid(keyed.out), centroid(xpbd.out));
  const Result back = run("simulate " + file.string() + " --frames 5 --threads 1 --integrator verlet");
  EXPECT_EQ(centroid(back.out), centroid(verlet.out));
}

TEST(ExitStatus, BenchWithoutOpenGlIsStatusThreeBeforeAnyRun) {
  const Result r = run("bench --solver gpu --sizes 8 --frames 1 --repeats 1 --warmup 0",
                       "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json");
  EXPECT_EQ(r.status, 3) << r.err;
  EXPECT_NE(r.err.find("OpenGL"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "no run before the check: " << r.err;
}

TEST(ExitStatus, BenchChecksItsOutputPathsBeforeAnyRun) {
  const fs::path dir = freshDir("bench_out");
  fs::create_symlink("/etc/passwd", dir / "bench.json");
  for (const std::string option : {"--json", "--markdown"}) {
    const Result r = run("bench --solver cpu --sizes 8 --frames 1 --repeats 1 --warmup 0 " + option + " " +
                         (dir / "bench.json").string());
    EXPECT_EQ(r.status, 2) << option << ": " << r.err;
    EXPECT_NE(r.err.find((dir / "bench.json").string()), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "no run before the check: " << r.err;
  }
  const Result r = run("bench --solver cpu --sizes 8 --frames 1 --repeats 1 --warmup 0 --json " +
                       (dir / "nowhere" / "bench.json").string());
  EXPECT_EQ(r.status, 2) << r.err;
}

TEST(ExitStatus, SimulateStatusesAsDocumented) {
  EXPECT_EQ(run("simulate " + scene("pinned2.json") + " --frames 1").status, 0);
  EXPECT_EQ(run("simulate /nonexistent.json").status, 2);
  EXPECT_EQ(run("simulate " + scene("pinned2.json") + " --frames 1 --solver gpu",
                "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json")
                .status,
            3);
  // ks far beyond the bound, with the guard's warning ignored: the cloth blows up.
  const fs::path file = writeScene("blow_up.json", cloth(R"(, "ks": 1e9)"));
  const Result r = run("simulate " + file.string() + " --frames 30");
  EXPECT_EQ(r.status, 4) << r.err;
}

TEST(ExitStatus, StabilityAndAccuracyRefuseAnOutThatIsAFile) {
  const fs::path file = writeScene("tiny_out.json", kTinyScene);
  std::ofstream(tempDir() / "a_file") << "x";
  EXPECT_EQ(run("stability --steps 1 --cases jittered --out " + (tempDir() / "a_file").string()).status, 2);
  EXPECT_EQ(
      run("accuracy " + file.string() + " --no-plot --out " + (tempDir() / "a_file").string() + kTinyAccuracy).status,
      2);
}

// ---------------------------------------------------------------------------------------------------
// The first five minutes: what a new user types before reading anything.

TEST(FirstMinutes, NoArgumentsPrintsTheHelpWithStatusZero) {
  const Result r = run("");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  for (const char* word : {"Usage", "simulate", "view", "render", "-f SCENE", "--version"})
    EXPECT_NE(r.out.find(word), std::string::npos) << word << " missing from:\n" << r.out;
}

TEST(FirstMinutes, VersionIsTheProjectsAndNamesTheDataDirectories) {
  const Result r = run("--version", "env -u DRAPE_GLSL_DIR -u DRAPE_TEXTURE_DIR");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.substr(0, r.out.find('\n')), std::string("drape ") + DRAPE_VERSION) << r.out;
  // The build tree's binary reads the source tree's files.
  for (const char* dir : {"glsl", "textures", "scenes"})
    EXPECT_NE(r.out.find(std::string(drape::test::sourceDir()) + "/" + dir + "\n"), std::string::npos)
        << dir << ": " << r.out;
  const Result moved = run("--version", "DRAPE_GLSL_DIR=/elsewhere/glsl");
  EXPECT_NE(moved.out.find("glsl      /elsewhere/glsl (missing)\n"), std::string::npos) << moved.out;
}

// CS184's viewer is started as `clothsim -f scene/pinned2.json`; drape takes the same words.
TEST(FirstMinutes, DashFOpensTheViewerOnTheScene) {
  const std::string no_display = "env -u DISPLAY -u WAYLAND_DISPLAY";
  Result r = run("-f " + scene("pinned2.json"), no_display);
  EXPECT_EQ(r.status, 3) << r.err;
  EXPECT_NE(r.err.find("view:"), std::string::npos) << "the viewer was asked for: " << r.err;
  EXPECT_NE(r.err.find("drape render"), std::string::npos) << "points to the headless command: " << r.err;
  // The scene is read (and refused) before any window: -f names the viewer's scene.
  r = run("-f /nonexistent/scene.json", no_display);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("/nonexistent/scene.json"), std::string::npos) << r.err;
  // The viewer's own options follow, as CS184's -a and -o do.
  r = run("-f " + scene("pinned2.json") + " -a 1", no_display);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("latitudes"), std::string::npos) << r.err;
  r = run("-f");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(FirstMinutes, StabilityHelpListsEveryCase) {
  const Result r = run("stability --help");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::vector<drape::StabilityCase> cases = drape::stabilityCases();
  ASSERT_FALSE(cases.empty());
  for (const drape::StabilityCase& c : cases)
    EXPECT_NE(r.out.find(c.name), std::string::npos) << c.name << " missing from:\n" << r.out;
}

// The installed README (share/doc/drape) shows its pictures and its links lead somewhere: every relative
// link of it and of the pages it links, images included, names a file that was installed.
TEST(FirstMinutes, TheInstalledReadmesPicturesAndLinksResolve) {
  const fs::path prefix = freshDir("installed_docs") / "prefix";
  const std::string install = "cmake --install " + quote(fs::path(drape::test::drapeBinary()).parent_path().string()) +
                              " --prefix " + quote(prefix.string()) + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(install.c_str()), 0) << install;
  const fs::path doc = prefix / "share" / "doc" / "drape";
  std::vector<fs::path> pages = {doc / "README.md"}, seen;
  std::size_t images = 0, links = 0;
  const std::regex link("\\]\\(([^)#\\s]+)[^)]*\\)");
  while (!pages.empty()) {
    const fs::path page = pages.back();
    pages.pop_back();
    if (std::find(seen.begin(), seen.end(), page) != seen.end()) continue;
    seen.push_back(page);
    std::ifstream in(page);
    std::stringstream text;
    text << in.rdbuf();
    const std::string md = text.str();
    ASSERT_FALSE(md.empty()) << page;
    for (auto it = std::sregex_iterator(md.begin(), md.end(), link); it != std::sregex_iterator(); ++it) {
      const std::string target = (*it)[1];
      if (target.rfind("http", 0) == 0) continue;
      const fs::path file = fs::weakly_canonical(page.parent_path() / target);
      EXPECT_TRUE(fs::exists(file)) << page << " links " << target;
      ++links;
      images += file.extension() == ".png";
      if (file.extension() == ".md" && fs::exists(file)) pages.push_back(file);
    }
  }
  EXPECT_GE(images, 11u + 10u + 6u) << "the gallery, the shading models and the fall";
  EXPECT_GT(seen.size(), 5u) << links << " links";
}

TEST(FirstMinutes, VideoWithoutFfmpegIsOneLineAndStatusOneBeforeAnyWork) {
  const fs::path dir = freshDir("no_ffmpeg");
  // drape is started by its full path; only its search for ffmpeg sees this PATH.
  const Result r = run("render " + scene("sphere.json") + " --frames 1 --out " + quote((dir / "o").string()) +
                           " --video " + quote((dir / "v.mp4").string()),
                       "PATH=" + quote((dir / "empty").string()));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("--video: ffmpeg is not installed"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "o")) << "checked before anything is made";
}

// A simulate of well over a second: on a terminal it shows its progress, through a pipe nothing. Its length
// in frames is measured on this machine (a short run first), so a faster machine or solver still gives a
// run long enough for progress to show: drape starts drawing after one second.
std::string longSimulate() {
  static const std::string command = [] {
    const std::string base = "simulate " + scene("selfCollision.json") + " --threads 1 --frames ";
    const int probe = 30;
    const auto start = std::chrono::steady_clock::now();
    const Result r = run(base + std::to_string(probe));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (r.status != 0) return base + "120";  // the test that runs it reports the failure
    const int frames = std::clamp(int(std::ceil(2.5 / std::max(seconds, 1e-3) * probe)), 120, 3000);
    return base + std::to_string(frames);
  }();
  return command;
}

TEST(FirstMinutes, SimulateThroughAPipeShowsNoProgress) {
  const auto start = std::chrono::steady_clock::now();
  const Result r = run(longSimulate());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(r.status, 0) << r.err;
  ASSERT_GT(seconds, 1.5) << "the run must be long enough that a terminal would show progress";
  EXPECT_TRUE(r.err.empty()) << "progress noise in a pipe: " << r.err;
}

TEST(FirstMinutes, SimulateOnATerminalShowsOneUpdatingLine) {
  if (std::system("command -v script >/dev/null 2>&1") != 0) GTEST_SKIP() << "no script(1) to make a terminal";
  // script(1) gives drape a terminal; drape's stdout goes to a file, so what script records is stderr.
  const fs::path dir = freshDir("tty");
  const std::string inner = std::string(drape::test::drapeBinary()) + " " + longSimulate() + " >" +
                            quote((dir / "summary").string()) + " </dev/null";
  const std::string command =
      "script -qec " + quote(inner) + " /dev/null >" + quote((dir / "tty").string()) + " 2>&1 </dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << slurp(dir / "tty");
  const std::string tty = slurp(dir / "tty");
  EXPECT_NE(tty.find("\rsimulate: frame "), std::string::npos) << tty;
  const std::string frames = longSimulate().substr(longSimulate().rfind(' ') + 1);
  EXPECT_NE(tty.find("/" + frames + ", "), std::string::npos) << tty;
  EXPECT_NE(tty.find("simulate: frame " + frames + "/" + frames), std::string::npos)
      << "the last frame is shown: " << tty;
  EXPECT_EQ(tty.back(), '\n') << "the line is finished, so the shell prompt starts on its own";
  EXPECT_NE(slurp(dir / "summary").find("max strain"), std::string::npos);
}

// `accuracy` rewrites its CSV as each run finishes; stopped by a signal, it keeps the runs it finished,
// each with all its rows. Twenty runs of a tiny cloth, one at a time: the signal comes after the first
// few and long before the last.
TEST(FirstMinutes, AnInterruptedAccuracyKeepsEveryFinishedRun) {
  const fs::path dir = freshDir("interrupted");
  std::ofstream(dir / "tiny.json") << kTinyScene;
  const fs::path csv = dir / "out" / "accuracy.csv";
  std::vector<std::string> args = {drape::test::drapeBinary(),
                                   "accuracy",
                                   (dir / "tiny.json").string(),
                                   "--out",
                                   (dir / "out").string(),
                                   "--no-plot",
                                   "--jobs",
                                   "1",
                                   "--solver",
                                   "cpu64,cpu",
                                   "--steps",
                                   "40,60,80,100,120,140,160,180,200,220",
                                   "--passes",
                                   "1",
                                   "--times",
                                   "1,2",
                                   "--reference-factor",
                                   "2"};
  std::vector<char*> argv;
  for (std::string& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, (dir / "stdout").c_str(), O_WRONLY | O_CREAT, 0600);
  posix_spawn_file_actions_addopen(&files, STDERR_FILENO, (dir / "stderr").c_str(), O_WRONLY | O_CREAT, 0600);
  // SIGINT at its default in the child: a test binary started in the background by a non-interactive
  // shell (tools/test's sanitizer shards) ignores SIGINT, and a spawned child would inherit that.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t interrupt;
  sigemptyset(&interrupt);
  sigaddset(&interrupt, SIGINT);
  posix_spawnattr_setsigdefault(&attributes, &interrupt);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, argv[0], &files, &attributes, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&files);
  posix_spawnattr_destroy(&attributes);
  // Three finished runs: the CSV then holds the header and their rows.
  auto runsIn = [](const std::string& text) {
    std::set<std::string> runs;
    std::istringstream lines(text);
    std::string line;
    std::getline(lines, line);
    while (std::getline(lines, line)) {
      std::size_t third = 0;
      for (int comma = 0; comma < 3 && third != std::string::npos; ++comma)
        third = line.find(',', third + (comma > 0));
      runs.insert(line.substr(0, third));
    }
    return runs;
  };
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (runsIn(slurp(csv)).size() < 3 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ::kill(pid, SIGINT);
  int raw = 0;
  ASSERT_EQ(::waitpid(pid, &raw, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(raw) && WTERMSIG(raw) == SIGINT)
      << "the sweep ended before the signal: " << slurp(dir / "stderr");

  const std::string text = slurp(csv);
  const std::set<std::string> runs = runsIn(text);
  EXPECT_GE(runs.size(), 3u) << text;
  EXPECT_LT(runs.size(), 20u) << "stopped before the end: " << text;
  // Every run in the file has both its sample times, and every line is whole.
  for (const std::string& run : runs) {
    std::size_t rows = 0;
    for (std::size_t at = text.find("\n" + run + ","); at != std::string::npos;
         at = text.find("\n" + run + ",", at + 1))
      ++rows;
    EXPECT_EQ(rows, 2u) << run << " in:\n" << text;
  }
  EXPECT_EQ(text.back(), '\n');
  EXPECT_TRUE(fs::exists(dir / "out" / "reference.csv"));
  for (const fs::directory_entry& e : fs::directory_iterator(dir / "out"))
    EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos) << "left behind: " << e.path();
}

// `cmake --install` puts drape, its shaders, textures and scenes under the prefix, and the installed
// drape reads its own copies: --version names them, and bench's default scenes come from there.
// tests/render_cli_gl_test.cpp shows that its shaders are read from there too.
TEST(Install, TheInstalledDrapeFindsItsDataBesideItself) {
  const fs::path prefix = freshDir("install") / "prefix";
  const fs::path build = fs::path(drape::test::drapeBinary()).parent_path();
  const std::string install =
      "cmake --install " + quote(build.string()) + " --prefix " + quote(prefix.string()) + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(install.c_str()), 0) << install;
  const fs::path drape = prefix / "bin" / "drape", share = prefix / "share" / "drape";
  ASSERT_TRUE(fs::exists(drape));
  for (const char* file : {"glsl/sim/forces_integrate.comp", "textures/fabric.png", "scenes/sphere.json",
                           "scenes/meshes", "tools/plot_accuracy.py"})
    EXPECT_TRUE(fs::exists(share / file)) << file;
  EXPECT_TRUE(fs::exists(prefix / "share" / "doc" / "drape" / "LICENSE"));

  const std::string env = "cd / && env -u DRAPE_GLSL_DIR -u DRAPE_TEXTURE_DIR " + quote(drape.string());
  const fs::path out = prefix.parent_path() / "version";
  ASSERT_EQ(std::system((env + " --version >" + quote(out.string())).c_str()), 0);
  const std::string version = slurp(out);
  for (const char* dir : {"glsl", "textures", "scenes"})
    EXPECT_NE(version.find(" " + (share / dir).string() + "\n"), std::string::npos) << version;
  EXPECT_EQ(version.find(drape::test::sourceDir()), std::string::npos) << "the source tree is not read: " << version;

  // The default scene of `bench` comes from the installed scenes/, from any directory.
  const std::string bench =
      env + " bench --solver cpu --sizes 4 --frames 1 --repeats 1 --warmup 0 >/dev/null 2>" + quote(out.string());
  EXPECT_EQ(std::system(bench.c_str()), 0) << slurp(out);
}

// A partial install: drape copied without its share/drape. It reads nothing of the machine it was built on
// (it used to take the build machine's source tree, silently): --version says what is missing, and the
// viewer's default scene is looked for, and refused, under its own prefix.
TEST(Install, ADrapeWithoutItsDataReadsNothingFromTheBuildMachine) {
  const fs::path prefix = freshDir("partial_install");
  fs::create_directories(prefix / "bin");
  std::error_code linked;
  fs::create_hard_link(drape::test::drapeBinary(), prefix / "bin" / "drape", linked);  // the same file, at another path
  if (linked) fs::copy_file(drape::test::drapeBinary(), prefix / "bin" / "drape");
  const fs::path share = prefix / "share" / "drape";
  const std::string drape = "cd / && env -u DRAPE_GLSL_DIR -u DRAPE_TEXTURE_DIR -u DISPLAY -u WAYLAND_DISPLAY " +
                            (prefix / "bin" / "drape").string();
  const fs::path out = prefix / "out", err = prefix / "err";
  ASSERT_EQ(std::system((drape + " --version >" + out.string()).c_str()), 0);
  const std::string version = slurp(out);
  EXPECT_EQ(version.find(drape::test::sourceDir()), std::string::npos) << version;
  for (const char* dir : {"glsl", "textures", "scenes"})
    EXPECT_NE(version.find(" " + (share / dir).string() + " (missing)\n"), std::string::npos) << version;
  const int raw = std::system((drape + " view >/dev/null 2>" + err.string() + " </dev/null").c_str());
  EXPECT_EQ(WEXITSTATUS(raw), 2) << slurp(err);
  EXPECT_NE(slurp(err).find((share / "scenes" / "sphere.json").string() + ": cannot open: no such file"),
            std::string::npos)
      << slurp(err);
}

}  // namespace
