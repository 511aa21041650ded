// The `drape` command line as a user meets it: runs the real binary as a subprocess.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

fs::path tempDir() {
  fs::path dir = fs::temp_directory_path() / ("drape_cli_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

Result run(const std::string& args) {
  const fs::path dir = tempDir();
  const std::string cmd = std::string(DRAPE_BINARY) + " " + args + " >" + (dir / "out").string() + " 2>" +
                          (dir / "err").string() + " </dev/null";
  int raw = std::system(cmd.c_str());
  Result r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  r.out = slurp(dir / "out");
  r.err = slurp(dir / "err");
  return r;
}

std::string scene(const std::string& name) {
  return std::string(DRAPE_SOURCE_DIR) + "/scenes/" + name;
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
        BadCase{"unknown_solver", cloth(""), "--solver quantum", "--solver"}),
    [](const auto& row) { return std::string(row.param.name); });

TEST(Cli, SimulatePrintsTheSummary) {
  Result r = run("simulate " + scene("pinned2.json") + " --frames 9");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* field : {"frames", "simulated", "y range", "centroid", "max strain", "ms per frame"})
    EXPECT_NE(r.out.find(field), std::string::npos) << field << " missing from:\n" << r.out;
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
  EXPECT_FALSE(fs::exists(out.string() + ".partial"));

  Result guarded = run("simulate " + path.string() + " --frames 30 --auto-substeps --out " + out.string());
  EXPECT_EQ(guarded.status, 0) << guarded.err;
  EXPECT_TRUE(fs::exists(out));
}

}  // namespace
