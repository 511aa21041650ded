// `drape render` and `drape view` as a user meets them: the real binary as a subprocess. The viewer
// runs under `xvfb-run` when there is no display.
#include "render/image.hpp"
#include "test_paths.hpp"

#include "shell_quote.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace drape {
namespace {

namespace fs = std::filesystem;

struct Result {
  int status = -1;
  std::string err;
};

class RenderCliTest : public ::testing::Test {
 protected:
  fs::path dir = fs::temp_directory_path() / ("drape_render_cli_" + std::to_string(::getpid()));
  void SetUp() override {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }

  // `prefix` goes before the binary (environment settings, xvfb-run).
  Result run(const std::string& args, const std::string& prefix = "") const {
    const std::string command = prefix + " " + drape::test::drapeBinary() + " " + args + " >/dev/null 2>'" +
                                (dir / "err").string() + "' </dev/null";
    const int raw = std::system(command.c_str());
    Result r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
    std::ifstream in(dir / "err");
    std::stringstream text;
    text << in.rdbuf();
    r.err = text.str();
    return r;
  }
};

std::string scene(const std::string& name) {
  return std::string(drape::test::sourceDir()) + "/scenes/" + name;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

bool have(const char* program) {
  return std::system(("command -v " + std::string(program) + " >/dev/null 2>&1").c_str()) == 0;
}

// Pixels clearly redder than the background and the grey sphere: the cloth's default colour.
std::size_t clothPixels(const Image& image) {
  std::size_t n = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.at(x, y);
      n += int(p[0]) > int(p[1]) + 40 && int(p[0]) > int(p[2]) + 40;
    }
  return n;
}

TEST_F(RenderCliTest, WritesTheFramesAskedFor) {
  const Result r = run("render " + scene("sphere.json") + " --frames 4 --every 2 --size 96x72 --shader toon --out '" +
                       (dir / "frames").string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir / "frames"))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"frame_0000.png", "frame_0002.png", "frame_0004.png"}));
  for (const std::string& name : names) {
    const Image image = loadImage(dir / "frames" / name, 3);
    EXPECT_EQ(image.width, 96);
    EXPECT_EQ(image.height, 72);
    EXPECT_GT(clothPixels(image), 100u) << name;
  }
  EXPECT_NE(r.err.find("frame 4/4"), std::string::npos) << "progress line: " << r.err;
}

TEST_F(RenderCliTest, CpuSolverRendersTheSameCoverage) {
  for (const char* solver : {"gpu", "cpu"}) {
    const Result r = run("render " + scene("sphere.json") + " --frames 0 --camera start --size 96x72 --solver " +
                         solver + " --out '" + (dir / solver).string() + "'");
    ASSERT_EQ(r.status, 0) << r.err;
  }
  const Image gpu = loadImage(dir / "gpu" / "frame_0000.png", 3), cpu = loadImage(dir / "cpu" / "frame_0000.png", 3);
  EXPECT_GT(clothPixels(gpu), 200u);
  EXPECT_EQ(clothPixels(gpu), clothPixels(cpu));
}

struct BadOption {
  const char* name;
  const char* args;
  const char* message;  // the one line must mention this
};

class RenderBadOptionTest : public RenderCliTest, public ::testing::WithParamInterface<BadOption> {};

TEST_P(RenderBadOptionTest, ExitsWithStatusTwoAndSaysWhy) {
  const BadOption& c = GetParam();
  std::string args = c.args;
  for (std::size_t at; (at = args.find("SCENE")) != std::string::npos;)
    args.replace(at, 5, scene("sphere.json"));
  for (std::size_t at; (at = args.find("OUT")) != std::string::npos;)
    args.replace(at, 3, (dir / "o").string());
  const Result r = run(args);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
}

// clang-format off
const BadOption kBadOptions[] = {
    {"unknown_shader", "render SCENE --out OUT --shader glossy", "glossy"},
    {"size_not_wxh", "render SCENE --out OUT --size 640", "--size"},
    {"size_too_small", "render SCENE --out OUT --size 4x4", "--size"},
    {"every_zero", "render SCENE --out OUT --every 0", "--every"},
    {"negative_frames", "render SCENE --out OUT --frames -3", "--frames"},
    {"unknown_solver", "render SCENE --out OUT --solver quantum", "--solver"},
    {"missing_out", "render SCENE", "--out"},
    {"missing_scene", "render /nonexistent/scene.json --out OUT", "/nonexistent/scene.json"},
    {"samples_zero", "render SCENE --out OUT --samples 0", "--samples"},
    {"frames_beyond_int", "render SCENE --out OUT --frames 99999999999", "--frames"},
    {"every_beyond_limit", "render SCENE --out OUT --every 2000000000", "--every"},
    {"view_unknown_shader", "view SCENE --shader glossy", "glossy"},
    {"view_screenshot_without_frames", "view SCENE --screenshot x.png", "--frames"},
    {"view_bad_tessellation", "view SCENE -a 1", "latitudes"},
};
// clang-format on

INSTANTIATE_TEST_SUITE_P(Cases, RenderBadOptionTest, ::testing::ValuesIn(kBadOptions),
                         [](const auto& test) { return std::string(test.param.name); });

TEST_F(RenderCliTest, NoOpenGlExitsWithStatusThree) {
  // glvnd finds no EGL vendor library here, so no context can be made.
  const Result r = run("render " + scene("sphere.json") + " --frames 1 --out '" + (dir / "o").string() + "'",
                       "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json");
  EXPECT_EQ(r.status, 3) << r.err;
  EXPECT_NE(r.err.find("OpenGL"), std::string::npos) << r.err;
}

TEST_F(RenderCliTest, VideoNeedsFfmpeg) {
  const Result r = run("render " + scene("sphere.json") + " --frames 2 --size 64x48 --out '" + (dir / "o").string() +
                       "' --video '" + (dir / "out.mp4").string() + "'");
  if (have("ffmpeg")) {
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_GT(fs::file_size(dir / "out.mp4"), 0u);
  } else {
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("ffmpeg is not installed"), std::string::npos) << r.err;
  }
}

using drape::testing::kHostile;
using drape::testing::quote;

TEST_F(RenderCliTest, FfmpegGetsHostileNamesAsArgumentsNotAsCommands) {
  // A stand-in ffmpeg first on $PATH records its arguments, one per line, and writes the video.
  fs::create_directories(dir / "bin");
  const fs::path ffmpeg = dir / "bin" / "ffmpeg";
  std::ofstream(ffmpeg) << "#!/bin/sh\nfor a in \"$@\"; do printf '%s\\n' \"$a\"; done > "
                        << quote((dir / "args").string())
                        << "\nfor a in \"$@\"; do last=\"$a\"; done\necho video > \"$last\"\n";
  fs::permissions(ffmpeg, fs::perms::owner_all);
  const fs::path out = dir / ("o" + kHostile), video = dir / ("v" + kHostile + ".mp4");
  const Result r = run("render " + scene("sphere.json") + " --frames 1 --size 32x32 --out " + quote(out.string()) +
                           " --video " + quote(video.string()),
                       "cd " + quote(dir.string()) + " && PATH=" + quote((dir / "bin").string()) + ":\"$PATH\"");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir / "PWNED")) << "a name ran a command";
  const std::string args = [&] {
    std::ifstream in(dir / "args");
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }();
  // ffmpeg writes a temporary of drape's beside the video, its extension kept; never the video itself.
  EXPECT_EQ(args.find("\n" + video.string() + "\n"), std::string::npos) << args;
  EXPECT_NE(args.find("\n" + (dir / ".drape-").string()), std::string::npos) << args;
  EXPECT_NE(args.find(".mp4\n"), std::string::npos) << args;
  EXPECT_EQ(slurp(video), "video\n");
}

// A stand-in ffmpeg: `body` runs with $out set to the file ffmpeg is told to write.
fs::path writeFfmpeg(const fs::path& dir, const std::string& body) {
  fs::create_directories(dir / "bin");
  const fs::path ffmpeg = dir / "bin" / "ffmpeg";
  std::ofstream(ffmpeg) << "#!/bin/sh\nfor a in \"$@\"; do out=\"$a\"; done\n" << body << "\n";
  fs::permissions(ffmpeg, fs::perms::owner_all);
  return dir / "bin";
}

std::vector<std::string> leftBehind(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().filename().string().rfind(".drape-", 0) == 0) names.push_back(entry.path().string());
  return names;
}

// The frames reach ffmpeg on its stdin, in order, exactly those this run wrote: the stand-in's video is
// what it read.
TEST_F(RenderCliTest, TheVideoHasExactlyTheFramesThisRunWroteOnePerShader) {
  const fs::path bin = writeFfmpeg(dir, "cat > \"$out\""), out = dir / "frames";
  // An earlier, longer run's frames in the same folders: they must not end up in this run's videos.
  for (const char* shader : {"toon", "normal"}) {
    fs::create_directories(out / shader);
    std::ofstream(out / shader / "frame_0009.png") << "stale";
  }
  const Result r = run("render " + scene("sphere.json") + " --frames 4 --every 2 --size 32x32 --shader toon,normal" +
                           " --out " + quote(out.string()) + " --video " + quote((dir / "v.mp4").string()),
                       "PATH=" + quote(bin.string()) + ":\"$PATH\"");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* shader : {"toon", "normal"}) {
    std::string frames;
    for (const char* frame : {"frame_0000.png", "frame_0002.png", "frame_0004.png"})
      frames += slurp(out / shader / frame);
    EXPECT_EQ(slurp(dir / ("v_" + std::string(shader) + ".mp4")), frames) << shader;
  }
  EXPECT_FALSE(fs::exists(dir / "v.mp4")) << "several shaders: one video each, none under the plain name";
  EXPECT_TRUE(leftBehind(dir).empty()) << leftBehind(dir).front();
}

// The race of issue 28: a link planted at the video while the run goes on. ffmpeg writes drape's
// temporary, which replaces the link: what it pointed to is untouched.
TEST_F(RenderCliTest, ALinkPlantedAtTheVideoMidRunIsReplacedNotWrittenThrough) {
  std::ofstream(dir / "victim") << "precious";
  const fs::path video = dir / "late.mp4";
  const fs::path bin = writeFfmpeg(dir, "ln -s victim " + quote(video.string()) + "\ncat > \"$out\"");
  const Result r = run("render " + scene("sphere.json") + " --frames 1 --size 32x32 --out " +
                           quote((dir / "frames").string()) + " --video " + quote(video.string()),
                       "PATH=" + quote(bin.string()) + ":\"$PATH\"");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(slurp(dir / "victim"), "precious");
  EXPECT_FALSE(fs::is_symlink(fs::symlink_status(video)));
  EXPECT_EQ(slurp(video), slurp(dir / "frames" / "frame_0000.png") + slurp(dir / "frames" / "frame_0001.png"));
  EXPECT_TRUE(leftBehind(dir).empty());
}

TEST_F(RenderCliTest, AFailingFfmpegLeavesTheVideoAsItWasAndNoTemporary) {
  std::ofstream(dir / "v.mp4") << "old video";
  const fs::path bin = writeFfmpeg(dir, "echo partial > \"$out\"\nexit 3");
  const Result r = run("render " + scene("sphere.json") + " --frames 1 --size 32x32 --out " +
                           quote((dir / "frames").string()) + " --video " + quote((dir / "v.mp4").string()),
                       "PATH=" + quote(bin.string()) + ":\"$PATH\"");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("--video: ffmpeg failed to write " + (dir / "v.mp4").string() + " (exit status 3)"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(slurp(dir / "v.mp4"), "old video");
  EXPECT_TRUE(leftBehind(dir).empty()) << leftBehind(dir).front();
}

// Checked before the first frame: the frames' folder is not even made.
TEST_F(RenderCliTest, AVideoFolderThatCannotTakeTheVideoIsRefusedBeforeAnyFrame) {
  const fs::path mount = dir / "readonly";
  fs::create_directories(mount);
  if (std::system(("mount -t tmpfs -o ro,size=16k tmpfs " + quote(mount.string()) + " 2>/dev/null").c_str()) != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here; AtomicFileTest.AReadOnlyFolderIsABadTargetBeforeAnyWrite covers it";
  const fs::path bin = writeFfmpeg(dir, "cat > \"$out\"");
  const Result r = run("render " + scene("sphere.json") + " --frames 2 --size 32x32 --out " +
                           quote((dir / "frames").string()) + " --video " + quote((mount / "v.mp4").string()),
                       "PATH=" + quote(bin.string()) + ":\"$PATH\"");
  std::system(("umount " + quote(mount.string())).c_str());
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find((mount / "v.mp4").string() + ": cannot create a file in its directory: Read-only file system"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "frames")) << "refused before any frame";
}

// kill -9 while ffmpeg runs: ffmpeg dies with drape, the video is untouched, no folder is left (drape's
// TMPDIR stays empty), and the next drape to write in the video's folder removes the stale temporary.
TEST_F(RenderCliTest, FfmpegDiesWithAKilledDrapeAndNothingIsLeftForLong) {
  std::ofstream(dir / "v.mp4") << "old video";
  fs::create_directories(dir / "tmp");
  const fs::path bin = writeFfmpeg(dir, "echo $$ > " + quote((dir / "ffmpeg.pid").string()) + "\nexec sleep 60");
  const std::string command = "PATH=" + quote(bin.string()) + ":\"$PATH\" TMPDIR=" + quote((dir / "tmp").string()) +
                              " exec " + drape::test::drapeBinary() + " render " + scene("sphere.json") +
                              " --frames 1 --size 32x32 --out " + quote((dir / "frames").string()) + " --video " +
                              quote((dir / "v.mp4").string()) + " 2>/dev/null";
  const pid_t drape = ::fork();
  ASSERT_GE(drape, 0);
  if (drape == 0) {
    ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  pid_t ffmpeg = 0;
  for (int i = 0; i < 6000 && ffmpeg <= 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::ifstream(dir / "ffmpeg.pid") >> ffmpeg;
  }
  ::kill(drape, SIGKILL);
  ::waitpid(drape, nullptr, 0);
  ASSERT_GT(ffmpeg, 0) << "ffmpeg never started";
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  const auto running = [&] {
    std::ifstream stat("/proc/" + std::to_string(ffmpeg) + "/stat");
    std::string text;
    return std::getline(stat, text) && text.find(") Z") == std::string::npos;
  };
  while (running() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_FALSE(running()) << "ffmpeg " << ffmpeg << " outlived drape";
  if (running()) ::kill(ffmpeg, SIGKILL);
  EXPECT_EQ(slurp(dir / "v.mp4"), "old video");
  EXPECT_TRUE(fs::is_empty(dir / "tmp")) << "a folder of drape's left in TMPDIR";
  const std::vector<std::string> stale = leftBehind(dir);
  ASSERT_EQ(stale.size(), 1u) << "the killed run's temporary";
  fs::last_write_time(stale.front(), fs::file_time_type::clock::now() - std::chrono::minutes(2));
  std::ofstream(dir / "tiny.json") << R"({"cloth": {"width": 1, "height": 1, "num_width_points": 4,
    "num_height_points": 4, "thickness": 0.01, "orientation": 0}})";
  ASSERT_EQ(run("simulate " + quote((dir / "tiny.json").string()) + " --frames 1 --out " +
                quote((dir / "positions.json").string()))
                .status,
            0);
  EXPECT_TRUE(leftBehind(dir).empty()) << "the next write in the folder removes it";
}

// The installed drape (cmake --install) compiles the shaders under its prefix: one broken there, and
// only there, stops its render with that file's name; whole again, the render works from any directory.
TEST_F(RenderCliTest, TheInstalledDrapeReadsItsOwnShaders) {
  const fs::path prefix = dir / "prefix";
  const std::string install = "cmake --install " + quote(fs::path(drape::test::drapeBinary()).parent_path().string()) +
                              " --prefix " + quote(prefix.string()) + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(install.c_str()), 0) << install;
  const fs::path shader = prefix / "share" / "drape" / "glsl" / "render" / "phong.frag";
  ASSERT_TRUE(fs::exists(shader));
  const std::string whole = [&] {
    std::ifstream in(shader);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }();
  std::ofstream(shader) << "this is not GLSL\n";
  const std::string env =
      "cd / && env -u DRAPE_GLSL_DIR -u DRAPE_TEXTURE_DIR " + quote((prefix / "bin" / "drape").string());
  const std::string args = " render " + scene("sphere.json") +
                           " --frames 0 --camera start --size 32x32 --solver cpu --out " + quote((dir / "o").string()) +
                           " >/dev/null";
  std::string command = env + args + " 2>" + quote((dir / "err").string());
  EXPECT_NE(std::system(command.c_str()), 0);
  std::ifstream broken_err(dir / "err");
  std::stringstream broken;
  broken << broken_err.rdbuf();
  EXPECT_NE(broken.str().find(shader.string()), std::string::npos) << broken.str();
  std::ofstream(shader) << whole;
  EXPECT_EQ(std::system(command.c_str()), 0);
  EXPECT_TRUE(fs::exists(dir / "o" / "frame_0000.png"));
}

TEST_F(RenderCliTest, AFullDiskIsStatusOneAndLeavesOnlyWholeFrames) {
  const fs::path mount = dir / "small";
  fs::create_directories(mount);
  if (std::system(("mount -t tmpfs -o size=48k tmpfs " + quote(mount.string()) + " 2>/dev/null").c_str()) != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here; AtomicFileTest covers the writer's errors";
  const Result r =
      run("render " + scene("sphere.json") + " --frames 20 --camera start --size 256x192 --shader normal --out " +
          quote((mount / "frames").string()));
  std::vector<fs::path> frames;
  for (const auto& entry : fs::directory_iterator(mount / "frames"))
    frames.push_back(entry.path());
  bool all_whole = true;
  for (const fs::path& frame : frames) {
    try {
      all_whole = loadImage(frame, 3).width == 256 && all_whole;
    } catch (const ImageError& e) {
      all_whole = false;
      ADD_FAILURE() << e.what();
    }
  }
  std::system(("umount " + quote(mount.string())).c_str());
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("No space left"), std::string::npos) << r.err;
  EXPECT_LT(frames.size(), 21u) << "48 KiB cannot hold 21 frames";
  EXPECT_TRUE(all_whole) << "a truncated or temporary file was left";
}

TEST_F(RenderCliTest, TooManySamplesIsStatusTwoNamingTheLimit) {
  const Result r = run("render " + scene("sphere.json") + " --frames 0 --size 32x32 --samples 16 --out '" +
                       (dir / "o").string() + "'");
  if (r.status == 0) GTEST_SKIP() << "this OpenGL allows 16 samples";
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("GL_MAX_SAMPLES"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "o")) << "nothing is made before the check";
}

TEST_F(RenderCliTest, AFailureBeforeRenderingLeavesNoDirectory) {
  const std::string out = " --frames 1 --out '" + (dir / "o").string() + "'";
  EXPECT_EQ(run("render /nonexistent/scene.json" + out).status, 2);
  EXPECT_FALSE(fs::exists(dir / "o"));
  EXPECT_EQ(run("render " + scene("sphere.json") + out, "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json").status, 3);
  EXPECT_FALSE(fs::exists(dir / "o"));
}

TEST_F(RenderCliTest, AnOutThatIsAFileOrAFrameThatIsALinkIsStatusTwo) {
  std::ofstream(dir / "file") << "x";
  Result r = run("render " + scene("sphere.json") + " --frames 0 --camera start --size 32x32 --out '" +
                 (dir / "file").string() + "'");
  EXPECT_EQ(r.status, 2) << r.err;
  fs::create_directories(dir / "frames");
  std::ofstream(dir / "victim") << "precious";
  fs::create_symlink(dir / "victim", dir / "frames" / "frame_0000.png");
  r = run("render " + scene("sphere.json") + " --frames 0 --camera start --size 32x32 --out '" +
          (dir / "frames").string() + "'");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("frame_0000.png"), std::string::npos) << r.err;
  std::ifstream in(dir / "victim");
  std::string text;
  in >> text;
  EXPECT_EQ(text, "precious");
}

TEST_F(RenderCliTest, ViewerWithoutDisplayExitsWithStatusThree) {
  const Result r = run("view " + scene("sphere.json") + " --frames 1", "env -u DISPLAY -u WAYLAND_DISPLAY");
  EXPECT_EQ(r.status, 3) << r.err;
  EXPECT_NE(r.err.find("drape render"), std::string::npos) << "should point to the headless command: " << r.err;
}

TEST_F(RenderCliTest, ViewerRunsSixtyFramesAndSavesAScreenshot) {
  const char* display = std::getenv("DISPLAY");
  const bool has_display = display && *display;
  if (!has_display && !have("xvfb-run")) GTEST_SKIP() << "no $DISPLAY and no xvfb-run (package xvfb) to make one";
  const fs::path shot = dir / "view.png";
  const Result r =
      run("view " + scene("sphere.json") + " --frames 60 --size 320x240 --screenshot '" + shot.string() + "'",
          has_display ? "" : "xvfb-run -a -s '-screen 0 640x480x24'");
  ASSERT_EQ(r.status, 0) << r.err;
  const Image image = loadImage(shot, 3);
  EXPECT_EQ(image.width, 320);
  EXPECT_EQ(image.height, 240);
  EXPECT_GT(clothPixels(image), 1000u) << "the cloth should be in view after 60 frames";
  // The viewer's camera, light and floor are `render`'s: the same frame of the same run is the same picture.
  const Result rendered = run("render " + scene("sphere.json") + " --frames 60 --every 60 --size 320x240 --out '" +
                              (dir / "render").string() + "'");
  ASSERT_EQ(rendered.status, 0) << rendered.err;
  const Image same = loadImage(dir / "render" / "frame_0060.png", 3);
  std::size_t differ = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c)
        if (std::abs(int(image.at(x, y)[c]) - int(same.at(x, y)[c])) > 2) {
          ++differ;
          break;
        }
  EXPECT_LT(differ, std::size_t(image.width * image.height / 200)) << "pixels differ from `render`'s frame 60";
}

}  // namespace
}  // namespace drape
