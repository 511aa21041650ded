// The commands' option helpers (src/app/options.hpp) on a real CLI11 app, and the solver table
// (src/app/solver_factory.hpp): what each bad value says, and that --help lists the choices.
#include "app/options.hpp"
#include "app/commands.hpp"
#include "app/solver_factory.hpp"
#include "app/suggest.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <optional>

namespace drape {
namespace {

// A command with the shapes of bench's and accuracy's lists and a positional after them.
struct ListCommand {
  CLI::App app{"test"};
  std::vector<int> sizes = {32, 64};
  std::vector<double> times = {0.5};
  std::vector<std::string> solvers = {"cpu"};
  std::string scene;
  ListCommand() {
    addListOption(&app, "--sizes", sizes, "sizes")->check(integerIn(2, 2048));
    addListOption(&app, "--times", times, "times")->check(positiveNumberUpTo(600));
    addListOption(&app, "--solver", solvers, "solvers")->check(CLI::IsMember(solverNames(true)));
    app.add_option("scene", scene, "scene");
  }
  // The usage error's one line, or nothing when the arguments parse.
  std::optional<std::string> parse(std::vector<std::string> args) {
    std::reverse(args.begin(), args.end());  // CLI11 takes them last first
    try {
      app.parse(args);
    } catch (const CLI::ParseError& e) {
      return std::string(e.what());
    }
    return std::nullopt;
  }
};

TEST(ListOptions, SplitAtCommasWithSpacesDropped) {
  ListCommand c;
  EXPECT_EQ(c.parse({"--sizes", "32, 64,128", "--times", "0.5,2", "--solver", "cpu64, gpu ", "s.json"}), std::nullopt);
  EXPECT_EQ(c.sizes, (std::vector<int>{32, 64, 128}));
  EXPECT_EQ(c.times, (std::vector<double>{0.5, 2.0}));
  EXPECT_EQ(c.solvers, (std::vector<std::string>{"cpu64", "gpu"}));
  EXPECT_EQ(c.scene, "s.json") << "a list option takes one argument, not the positional after it";
}

TEST(ListOptions, AnOptionNotGivenKeepsItsDefault) {
  ListCommand c;
  EXPECT_EQ(c.parse({"--times", "1"}), std::nullopt);
  EXPECT_EQ(c.sizes, (std::vector<int>{32, 64}));
  EXPECT_EQ(c.solvers, (std::vector<std::string>{"cpu"}));
}

TEST(ListOptions, EachBadItemIsNamedInOneLine) {
  const std::pair<std::vector<std::string>, std::string> cases[] = {
      {{"--sizes", "32,x"}, "--sizes: 'x' is not an integer"},
      {{"--sizes", "1"}, "--sizes: 1 is below the minimum 2"},
      {{"--sizes", "4096"}, "--sizes: 4096 is above the maximum 2048"},
      {{"--sizes", "99999999999"}, "--sizes: 99999999999 is above the maximum 2048"},
      {{"--sizes", "-99999999999"}, "--sizes: -99999999999 is below the minimum 2"},
      {{"--sizes", "8.5"}, "--sizes: '8.5' is not an integer"},
      {{"--sizes", ""}, "--sizes: '' is not an integer"},
      {{"--sizes", "8", "--sizes", "16"}, "--sizes: given more than once"},
      {{"--times", "-1"}, "--times: '-1' is not a positive number"},
      {{"--times", "nan"}, "--times: 'nan' is not a positive number"},
      {{"--times", "601"}, "--times: 601 is above the maximum 600"},
      {{"--solver", "cpu,cuda"}, "--solver: cuda not in {"},
  };
  for (const auto& [args, message] : cases) {
    ListCommand c;
    const std::optional<std::string> error = c.parse(args);
    ASSERT_TRUE(error.has_value()) << args.back();
    EXPECT_EQ(error->find(message), 0u) << *error;
    EXPECT_EQ(error->find('\n'), std::string::npos) << *error;
  }
}

TEST(ListOptions, HelpListsTheChoicesAndDefaults) {
  ListCommand c;
  const std::string help = c.app.help();
  EXPECT_NE(help.find("cpu,cpu64,gpu,gpu-general,gpu-tiled,gpu-onedispatch,cpu-xprev"), std::string::npos) << help;
  EXPECT_NE(help.find("32,64"), std::string::npos) << help;
  EXPECT_NE(help.find("INT in [2 .. 2048]"), std::string::npos) << help;
}

TEST(Sizes, WidthByHeightWithinBounds) {
  EXPECT_EQ(parseSize("--size", "640x480", 16, 8192), glm::ivec2(640, 480));
  EXPECT_EQ(parseSize("--size", "16x8192", 16, 8192), glm::ivec2(16, 8192));
  for (const char* bad : {"640", "640x", "x480", "640X480", "-640x480", "15x480", "640x8193", "123456x1"}) {
    try {
      parseSize("--size", bad, 16, 8192);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const CommandError& e) {
      EXPECT_EQ(e.status(), kExitBadInput) << bad;
      EXPECT_EQ(std::string(e.what()).rfind("--size: ", 0), 0u) << e.what();
    }
  }
  // Too large is out of range, however many digits: not "not WIDTHxHEIGHT".
  for (const char* large : {"100000x100000", "640x99999999999999999999", "0000640x0000000000480000"}) {
    try {
      parseSize("--size", large, 16, 8192);
      ADD_FAILURE() << large << " was accepted";
    } catch (const CommandError& e) {
      EXPECT_EQ(std::string(e.what()), fmt::format("--size: {} is outside 16x16 .. 8192x8192", large));
    }
  }
  EXPECT_EQ(parseSize("--size", "000640x0480", 16, 8192), glm::ivec2(640, 480));
}

TEST(SolverTable, EveryNameMakesThatSolverAndOnlyMeasurementsGetCpuXprev) {
  EXPECT_EQ(solverNames(false),
            (std::vector<std::string>{"cpu", "cpu64", "gpu", "gpu-general", "gpu-tiled", "gpu-onedispatch"}));
  EXPECT_EQ(solverNames(true), (std::vector<std::string>{"cpu", "cpu64", "gpu", "gpu-general", "gpu-tiled",
                                                         "gpu-onedispatch", "cpu-xprev"}));
  Scene scene;
  scene.cloth.num_width_points = 4;
  scene.cloth.num_height_points = 4;
  SolverFactory factory;
  for (const std::string& name : solverNames(true)) {
    if (isGpuSolver(name)) continue;  // needs GL: tests/gpu_solver_gl_test.cpp and the CLI tests
    EXPECT_EQ(factory.make(scene, name, {.threads = 1})->name(), name);
  }
}

}  // namespace
}  // namespace drape

namespace drape {
namespace {

TEST(DidYouMean, EditDistanceCountsASwapAsOneEdit) {
  EXPECT_EQ(editDistance("--verison", "--version"), 1);
  EXPECT_EQ(editDistance("--frame", "--frames"), 1);
  EXPECT_EQ(editDistance("--evry", "--every"), 1);
  EXPECT_EQ(editDistance("simulat", "simulate"), 1);
  EXPECT_EQ(editDistance("abc", "abc"), 0);
  EXPECT_EQ(editDistance("", "abc"), 3);
}

TEST(DidYouMean, OnlyANearWordIsSuggested) {
  const std::vector<std::string> options = {"--frames", "--every", "--export", "--format", "--out"};
  EXPECT_EQ(closestWord("--frame", options), "--frames");
  EXPECT_EQ(closestWord("--fromat", options), "--format");
  EXPECT_EQ(closestWord("--colour", options), "");
  EXPECT_EQ(closestWord("--x", options), "");
}

}  // namespace
}  // namespace drape
