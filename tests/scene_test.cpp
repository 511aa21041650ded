// Scene loading: every malformed input is refused with "<file>: <key>: <problem>", every shipped scene
// loads, the CS184 scenes carry CS184's values, and omitted optional keys take the documented defaults.
#include "core/scene.hpp"
#include "core/stability.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <string>
#include <thread>
#include <vector>

namespace drape {
namespace {

namespace fs = std::filesystem;

const fs::path kScenesDir = fs::path(drape::test::sourceDir()) / "scenes";

// A valid scene using every key, so that each bad case below changes exactly one thing.
nlohmann::json fullScene() {
  return nlohmann::json::parse(R"({
    "cloth": {"width": 1, "height": 1, "num_width_points": 4, "num_height_points": 3, "thickness": 0.01,
              "orientation": 0, "pinned": [[0, 0], [3, 2]], "enable_structural": true, "enable_shearing": true,
              "enable_bending": true, "damping": 0.2, "density": 150, "ks": 5000},
    "sphere": {"origin": [0.5, 0.2, 0.5], "radius": 0.2, "friction": 0.3},
    "plane": {"point": [0, 0, 0], "normal": [0, 1, 0], "friction": 0.5},
    "spheres": [{"origin": [0, 0, 0], "radius": 0.1, "friction": 0.1}],
    "planes": [{"point": [0, -1, 0], "normal": [0, 1, 0], "friction": 0.2}],
    "simulation": {"frames_per_sec": 90, "steps_per_frame": 30, "gravity": [0, -9.8, 0], "self_collision": true,
                   "stretch_passes": 1, "stretch_limit": 1.1,
                   "wind": {"enabled": true, "velocity": [1, 0, 0], "turbulence": 0.1, "noise_scale": 1,
                            "noise_speed": 1, "drag": 1}}
  })");
}

// Required cloth keys only, for scenes written as raw text.
const std::string kCloth =
    R"("cloth": {"width": 1, "height": 1, "num_width_points": 4, "num_height_points": 3, "thickness": 0.01,
                 "orientation": 0})";

// Expects SceneError whose single line starts with "<file>: <key>: " and names the problem.
void expectRejected(const std::string& text, const std::string& file, const std::string& key,
                    const std::string& problem) {
  try {
    parseScene(text, file);
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const SceneError& e) {
    std::string message = e.what();
    EXPECT_EQ(message.rfind(file + ": " + key + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(problem), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

// ---------------------------------------------------------------------------------------------------
// One change (a JSON merge patch, RFC 7386: null removes a key) applied to the full scene.
struct PatchCase {
  std::string name;
  std::string patch;
  std::string key;
  std::string problem;
};

class BadPatch : public testing::TestWithParam<PatchCase> {};

TEST_P(BadPatch, IsRejectedNamingFileKeyAndProblem) {
  const PatchCase& c = GetParam();
  nlohmann::json scene = fullScene();
  scene.merge_patch(nlohmann::json::parse(c.patch));
  expectRejected(scene.dump(2), c.name + ".json", c.key, c.problem);
}

// clang-format off
const PatchCase kPatchCases[] = {
  // unknown keys at every level
  {"unknown_top_key", R"({"clth": {}})", "clth", "unknown key"},
  {"unknown_cloth_key", R"({"cloth": {"kss": 1}})", "cloth.kss", "unknown key (did you mean 'ks'?)"},
  {"unknown_sphere_key", R"({"sphere": {"centre": [0, 0, 0]}})", "sphere.centre", "unknown key"},
  {"unknown_plane_key", R"({"plane": {"offset": 1}})", "plane.offset", "unknown key"},
  {"unknown_spheres_key", R"({"spheres": [{"origin": [0, 0, 0], "radius": 1, "colour": 1}]})", "spheres[0].colour", "unknown key"},
  {"unknown_planes_key", R"({"planes": [{"point": [0, 0, 0], "normal": [0, 1, 0], "fricton": 1}]})", "planes[0].fricton", "unknown key (did you mean 'friction'?)"},
  {"unknown_simulation_key", R"({"simulation": {"substeps": 3}})", "simulation.substeps", "unknown key"},
  {"unknown_wind_key", R"({"simulation": {"wind": {"speed": 3}}})", "simulation.wind.speed", "unknown key"},
  // missing required keys
  {"missing_cloth", R"({"cloth": null})", "cloth", "missing required key"},
  {"missing_width", R"({"cloth": {"width": null}})", "cloth.width", "missing required key"},
  {"missing_height", R"({"cloth": {"height": null}})", "cloth.height", "missing required key"},
  {"missing_num_width_points", R"({"cloth": {"num_width_points": null}})", "cloth.num_width_points", "missing required key"},
  {"missing_num_height_points", R"({"cloth": {"num_height_points": null}})", "cloth.num_height_points", "missing required key"},
  {"missing_thickness", R"({"cloth": {"thickness": null}})", "cloth.thickness", "missing required key"},
  {"missing_orientation", R"({"cloth": {"orientation": null}})", "cloth.orientation", "missing required key"},
  {"missing_sphere_origin", R"({"sphere": {"origin": null}})", "sphere.origin", "missing required key"},
  {"missing_sphere_radius", R"({"sphere": {"radius": null}})", "sphere.radius", "missing required key"},
  {"missing_plane_point", R"({"plane": {"point": null}})", "plane.point", "missing required key"},
  {"missing_plane_normal", R"({"plane": {"normal": null}})", "plane.normal", "missing required key"},
  // wrong types
  {"cloth_not_object", R"({"cloth": [1, 2]})", "cloth", "expected an object, got array"},
  {"ks_string", R"({"cloth": {"ks": "5000"}})", "cloth.ks", "expected a number, got string"},
  {"width_boolean", R"({"cloth": {"width": true}})", "cloth.width", "expected a number, got boolean"},
  {"points_string", R"({"cloth": {"num_width_points": "4"}})", "cloth.num_width_points", "expected a number, got string"},
  {"points_fraction", R"({"cloth": {"num_height_points": 3.5}})", "cloth.num_height_points", "expected an integer"},
  {"enable_bending_number", R"({"cloth": {"enable_bending": 1}})", "cloth.enable_bending", "expected true or false, got number"},
  {"orientation_string", R"({"cloth": {"orientation": "vertical"}})", "cloth.orientation", "expected a number, got string"},
  {"pinned_object", R"({"cloth": {"pinned": {"x": 0}}})", "cloth.pinned", "expected an array, got object"},
  {"origin_two_numbers", R"({"sphere": {"origin": [0, 0]}})", "sphere.origin", "expected [x, y, z]"},
  {"origin_string_element", R"({"sphere": {"origin": [0, "1", 0]}})", "sphere.origin[1]", "expected a number, got string"},
  {"spheres_object", R"({"spheres": {"origin": [0, 0, 0], "radius": 1}})", "spheres", "expected an array, got object"},
  {"sphere_array", R"({"sphere": [0, 0, 0]})", "sphere", "expected an object, got array"},
  {"simulation_number", R"({"simulation": 3})", "simulation", "expected an object, got number"},
  {"gravity_string", R"({"simulation": {"gravity": "down"}})", "simulation.gravity", "expected [x, y, z]"},
  {"self_collision_string", R"({"simulation": {"self_collision": "yes"}})", "simulation.self_collision", "expected true or false, got string"},
  {"steps_fraction", R"({"simulation": {"steps_per_frame": 2.5}})", "simulation.steps_per_frame", "expected an integer"},
  {"wind_number", R"({"simulation": {"wind": 3}})", "simulation.wind", "expected an object, got number"},
  {"wind_enabled_string", R"({"simulation": {"wind": {"enabled": "no"}}})", "simulation.wind.enabled", "expected true or false"},
  // grid size
  {"width_points_1", R"({"cloth": {"num_width_points": 1}})", "cloth.num_width_points", "must be >= 2 (got 1)"},
  {"height_points_0", R"({"cloth": {"num_height_points": 0}})", "cloth.num_height_points", "must be >= 2 (got 0)"},
  {"height_points_negative", R"({"cloth": {"num_height_points": -7}})", "cloth.num_height_points", "must be >= 2"},
  {"width_points_beyond_int", R"({"cloth": {"num_width_points": 1e10}})", "cloth.num_width_points", "must be <="},
  {"grid_too_large", R"({"cloth": {"num_width_points": 5000, "num_height_points": 5000}})", "cloth", "grid too large"},
  // non-positive sizes and material
  {"width_zero", R"({"cloth": {"width": 0}})", "cloth.width", "must be > 0"},
  {"height_negative", R"({"cloth": {"height": -1}})", "cloth.height", "must be > 0"},
  {"density_zero", R"({"cloth": {"density": 0}})", "cloth.density", "must be > 0"},
  {"density_negative", R"({"cloth": {"density": -150}})", "cloth.density", "must be > 0"},
  {"thickness_zero", R"({"cloth": {"thickness": 0}})", "cloth.thickness", "must be > 0"},
  {"ks_negative", R"({"cloth": {"ks": -5}})", "cloth.ks", "must be > 0"},
  {"damping_negative", R"({"cloth": {"damping": -0.1}})", "cloth.damping", "must be in [0, 100]"},
  {"damping_over_100", R"({"cloth": {"damping": 100.5}})", "cloth.damping", "must be in [0, 100]"},
  // colliders
  {"sphere_friction_over_1", R"({"sphere": {"friction": 1.5}})", "sphere.friction", "must be in [0, 1]"},
  {"plane_friction_negative", R"({"plane": {"friction": -0.1}})", "plane.friction", "must be in [0, 1]"},
  {"planes_friction_over_1", R"({"planes": [{"point": [0, 0, 0], "normal": [0, 1, 0], "friction": 2}]})", "planes[0].friction", "must be in [0, 1]"},
  {"radius_zero", R"({"sphere": {"radius": 0}})", "sphere.radius", "must be > 0"},
  {"radius_negative", R"({"sphere": {"radius": -1}})", "sphere.radius", "must be > 0"},
  {"spheres_radius_zero", R"({"spheres": [{"origin": [0, 0, 0], "radius": 1}, {"origin": [0, 0, 0], "radius": 0}]})", "spheres[1].radius", "must be > 0"},
  {"normal_zero", R"({"plane": {"normal": [0, 0, 0]}})", "plane.normal", "zero length"},
  {"planes_normal_zero", R"({"planes": [{"point": [0, 0, 0], "normal": [0.0, -0.0, 0]}]})", "planes[0].normal", "zero length"},
  // pins
  {"pin_x_outside", R"({"cloth": {"pinned": [[0, 0], [4, 0]]}})", "cloth.pinned[1]", "outside the 4 x 3 grid"},
  {"pin_y_outside", R"({"cloth": {"pinned": [[0, 3]]}})", "cloth.pinned[0]", "outside the 4 x 3 grid"},
  {"pin_negative", R"({"cloth": {"pinned": [[-1, 0]]}})", "cloth.pinned[0]", "outside the 4 x 3 grid"},
  {"pin_one_number", R"({"cloth": {"pinned": [[1]]}})", "cloth.pinned[0]", "expected [x, y]"},
  {"pin_three_numbers", R"({"cloth": {"pinned": [[1, 2, 3]]}})", "cloth.pinned[0]", "expected [x, y]"},
  {"pin_not_array", R"({"cloth": {"pinned": [5]}})", "cloth.pinned[0]", "expected an array, got number"},
  {"pin_string", R"({"cloth": {"pinned": [["a", 0]]}})", "cloth.pinned[0][0]", "expected a number, got string"},
  {"pin_fraction", R"({"cloth": {"pinned": [[1.5, 0]]}})", "cloth.pinned[0][0]", "expected an integer"},
  // enumerations
  {"orientation_2", R"({"cloth": {"orientation": 2}})", "cloth.orientation", "must be 0 (horizontal) or 1 (vertical)"},
  {"orientation_negative", R"({"cloth": {"orientation": -1}})", "cloth.orientation", "must be 0 (horizontal) or 1 (vertical)"},
  // simulation
  {"fps_zero", R"({"simulation": {"frames_per_sec": 0}})", "simulation.frames_per_sec", "must be > 0"},
  {"fps_negative", R"({"simulation": {"frames_per_sec": -90}})", "simulation.frames_per_sec", "must be > 0"},
  {"steps_zero", R"({"simulation": {"steps_per_frame": 0}})", "simulation.steps_per_frame", "must be >= 1"},
  {"stretch_passes_negative", R"({"simulation": {"stretch_passes": -1}})", "simulation.stretch_passes", "must be >= 0"},
  {"stretch_scheme_unknown", R"({"simulation": {"stretch_scheme": "sor"}})", "simulation.stretch_scheme",
   "unknown scheme 'sor'"},
  {"stretch_scheme_number", R"({"simulation": {"stretch_scheme": 1}})", "simulation.stretch_scheme",
   "expected a string"},
  {"integrator_unknown", R"({"simulation": {"integrator": "rk4"}})", "simulation.integrator",
   "unknown integrator 'rk4' (verlet, xpbd or vbd)"},
  {"integrator_number", R"({"simulation": {"integrator": 1}})", "simulation.integrator", "expected a string"},
  {"integrator_case", R"({"simulation": {"integrator": "XPBD"}})", "simulation.integrator", "unknown integrator 'XPBD'"},
  {"iterations_zero", R"({"simulation": {"iterations": 0}})", "simulation.iterations", "must be >= 1"},
  {"iterations_fraction", R"({"simulation": {"iterations": 1.5}})", "simulation.iterations", "expected an integer"},
  {"iterations_string", R"({"simulation": {"iterations": "2"}})", "simulation.iterations", "expected a number, got string"},
  {"iterations_endless", R"({"simulation": {"iterations": 2000000000}})", "simulation.iterations", "must be <= 100 (got 2000000000)"},
  {"stretch_limit_below_1", R"({"simulation": {"stretch_limit": 0.9}})", "simulation.stretch_limit", "must be >= 1"},
  {"tethers_number", R"({"simulation": {"tethers": 1}})", "simulation.tethers", "expected true or false, got number"},
  {"wind_noise_scale_zero", R"({"simulation": {"wind": {"noise_scale": 0}}})", "simulation.wind.noise_scale", "must be > 0"},
  {"wind_drag_negative", R"({"simulation": {"wind": {"drag": -1}}})", "simulation.wind.drag", "must be >= 0"},
  {"wind_turbulence_negative", R"({"simulation": {"wind": {"turbulence": -0.5}}})", "simulation.wind.turbulence", "must be >= 0"},
  {"wind_noise_speed_negative", R"({"simulation": {"wind": {"noise_speed": -1}}})", "simulation.wind.noise_speed", "must be >= 0"},
  {"wind_velocity_short", R"({"simulation": {"wind": {"velocity": [1, 0]}}})", "simulation.wind.velocity", "expected [x, y, z]"},
  // values that vanish or overflow in float, where the solvers compute
  {"thickness_vanishes", R"({"cloth": {"thickness": 1e-300}})", "cloth.thickness", "too small: 1e-300 is 0 or denormal in float"},
  {"thickness_denormal", R"({"cloth": {"thickness": 1e-40}})", "cloth.thickness", "too small"},
  {"noise_scale_vanishes", R"({"simulation": {"wind": {"noise_scale": 1e-300}}})", "simulation.wind.noise_scale", "too small"},
  {"density_vanishes", R"({"cloth": {"density": 1e-300}})", "cloth.density", "too small"},
  {"fps_vanishes", R"({"simulation": {"frames_per_sec": 1e-300}})", "simulation.frames_per_sec", "too small"},
  {"ks_beyond_float", R"({"cloth": {"ks": 1e300}})", "cloth.ks", "out of float range"},
  {"gravity_beyond_float", R"({"simulation": {"gravity": [0, -1e39, 0]}})", "simulation.gravity[1]", "out of float range"},
  {"origin_beyond_float", R"({"sphere": {"origin": [1e300, 0, 0]}})", "sphere.origin[0]", "out of float range"},
  {"mass_vanishes", R"({"cloth": {"width": 1e-20, "height": 1e-20}})", "cloth", "mass per point"},
  {"mass_overflows", R"({"cloth": {"width": 1e20, "height": 1e20, "density": 1e20}})", "cloth", "mass per point"},
  {"spacing_vanishes", R"({"cloth": {"width": 2e-38, "density": 1e30}})", "cloth", "point spacing"},
  {"time_step_vanishes", R"({"simulation": {"frames_per_sec": 1e30}})", "simulation.frames_per_sec", "time step"},
  {"time_step_squared_overflows", R"({"simulation": {"frames_per_sec": 1e-30}})", "simulation.frames_per_sec", "time step"},
  // counts that would run forever
  {"steps_endless", R"({"simulation": {"steps_per_frame": 2000000000}})", "simulation.steps_per_frame", "must be <= 10000 (got 2000000000)"},
  {"steps_above_limit", R"({"simulation": {"steps_per_frame": 10001}})", "simulation.steps_per_frame", "must be <= 10000"},
  {"stretch_passes_endless", R"({"simulation": {"stretch_passes": 2000000000}})", "simulation.stretch_passes", "must be <= 100 (got 2000000000)"},
  {"grid_above_limit", R"({"cloth": {"num_width_points": 2049, "num_height_points": 2048}})", "cloth", "grid too large"},
};
// clang-format on

INSTANTIATE_TEST_SUITE_P(Scene, BadPatch, testing::ValuesIn(kPatchCases),
                         [](const testing::TestParamInfo<PatchCase>& p) { return p.param.name; });

// ---------------------------------------------------------------------------------------------------
// Inputs that are not a change to a valid scene: broken syntax, duplicates, overflow, wrong top level.
struct RawCase {
  std::string name;
  std::string text;
  std::string key;  // or "line L, column C" for syntax errors
  std::string problem;
};

class BadText : public testing::TestWithParam<RawCase> {};

TEST_P(BadText, IsRejectedNamingFileKeyAndProblem) {
  const RawCase& c = GetParam();
  expectRejected(c.text, c.name + ".json", c.key, c.problem);
}

// clang-format off
const RawCase kRawCases[] = {
  {"syntax_missing_value", "{\n  \"cloth\": {\n    \"width\": ,\n  }\n}", "line 3, column 14", "invalid JSON"},
  {"syntax_bad_literal", "{\n  \"cloth\": tru\n}", "line 2, column 14", "invalid JSON"},
  {"syntax_unterminated", "{\n  \"cloth\": {\"width\": 1,\n", "line 2, column 23", "unexpected end of input"},
  {"syntax_trailing_garbage", "{" + kCloth + "} x", "line 2, column 37", "invalid JSON"},
  {"syntax_single_quotes", "{'cloth': 1}", "line 1, column 2", "invalid JSON"},
  {"empty_text", "", "line 1, column 1", "invalid JSON"},
  {"whitespace_only", "  \n  ", "line 1, column 1", "invalid JSON"},
  {"overflow_ks", "{\"cloth\": {\"ks\": 1e999}}", "cloth.ks", "number too large"},
  {"overflow_negative", "{" + kCloth + ", \"sphere\": {\"origin\": [0, -1e999, 0], \"radius\": 1}}", "sphere.origin[1]", "number too large"},
  {"overflow_in_pins", "{\"cloth\": {\"pinned\": [[0, 0], [1e400, 0]]}}", "cloth.pinned[1][0]", "number too large"},
  {"duplicate_cloth_key", "{\"cloth\": {\"ks\": 1, \"ks\": 2}}", "cloth.ks", "duplicate key"},
  {"duplicate_top_key", "{" + kCloth + ", " + kCloth + "}", "cloth", "duplicate key"},
  {"duplicate_in_list", "{" + kCloth + ", \"spheres\": [{\"radius\": 1}, {\"radius\": 1, \"radius\": 2}]}", "spheres[1].radius", "duplicate key"},
  {"escaped_key", R"({"cloth": {"k\ns": 1}})", R"(cloth."k\ns")", "unknown key"},
  {"top_level_array", "[1, 2]", "top level", "expected an object, got array"},
  {"top_level_number", "3", "top level", "expected an object, got number"},
  {"empty_object", "{}", "cloth", "missing required key"},
  {"deep_nesting", "{\"x\": " + std::string(100, '[') + std::string(100, ']') + "}", [] { std::string p = "x"; for (int i = 0; i < 31; ++i) p += "[0]"; return p; }(), "nested more than 32 levels"},
};
// clang-format on

INSTANTIATE_TEST_SUITE_P(Scene, BadText, testing::ValuesIn(kRawCases),
                         [](const testing::TestParamInfo<RawCase>& p) { return p.param.name; });

// ---------------------------------------------------------------------------------------------------
TEST(SceneFile, MissingFileIsRejected) {
  const std::string path = (fs::temp_directory_path() / "drape_no_such_scene.json").string();
  try {
    loadScene(path);
    ADD_FAILURE() << "loaded a missing file";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": cannot open: no such file");
  }
}

TEST(SceneFile, DirectoryIsRejected) {
  try {
    loadScene(kScenesDir);
    ADD_FAILURE() << "loaded a directory";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), kScenesDir.string() + ": cannot open: is a directory, not a file");
  }
}

TEST(SceneFile, ErrorsInAFileNameThePath) {
  const fs::path path = fs::temp_directory_path() / "drape_scene_test_bad.json";
  std::ofstream(path) << "{" << kCloth << ",\n  \"plane\": {\"point\": [0, 0, 0], \"normal\": [0, 0, 0]}}";
  try {
    loadScene(path);
    ADD_FAILURE() << "loaded a zero normal";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), path.string() + ": plane.normal: zero length, a plane needs a direction");
  }
  fs::remove(path);
}

// ---------------------------------------------------------------------------------------------------
std::vector<std::string> sceneFiles() {
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(kScenesDir)) {
    if (entry.path().extension() == ".json") files.push_back(entry.path().filename().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(ShippedScenes, IncludeTheStandardAndExtensionScenes) {
  std::vector<std::string> files = sceneFiles();
  for (const char* name : {"pinned2.json", "pinned4.json", "sphere.json", "plane.json", "selfCollision.json",
                           "wind.json", "two_spheres.json"}) {
    EXPECT_NE(std::find(files.begin(), files.end(), name), files.end()) << name;
  }
}

class ShippedScene : public testing::TestWithParam<std::string> {};

// Loads, and runs inside the explicit-integration bound at its own substep count (the bound itself is
// checked by simulation in tests/stability_test.cpp).
TEST_P(ShippedScene, LoadsAndIsInsideTheStabilityBound) {
  Scene scene = loadScene(kScenesDir / GetParam());
  EXPECT_EQ(scene.path, (kScenesDir / GetParam()).string());
  const StabilityCheck check = checkStability(scene);
  EXPECT_TRUE(check.ok) << check.message;
}

INSTANTIATE_TEST_SUITE_P(Scenes, ShippedScene, testing::ValuesIn(sceneFiles()),
                         [](const testing::TestParamInfo<std::string>& p) {
                           std::string name = fs::path(p.param).stem().string();
                           std::replace_if(
                               name.begin(), name.end(), [](char ch) { return !std::isalnum(ch); }, '_');
                           return name;
                         });

// The five CS184 scenes as the course publishes them (the scene/ directory of the CS184 ClothSim
// starter code): the same material and grid in all five, differing in orientation, pins and
// colliders. Our files must load to exactly what these load to; the only change allowed is the
// `simulation` extension, which pinned2 and pinned4 use to turn self-collision off (scenes/README.md).
constexpr const char* kCs184Material =
    R"("damping": 0.2, "density": 150.0, "ks": 5000.0, "enable_structural": true, "enable_shearing": true,
       "enable_bending": true, "width": 1, "height": 1, "num_width_points": 50, "num_height_points": 50,
       "thickness": 0.0095)";

struct Cs184Case {
  std::string name;
  std::string published;  // the course's file, with the shared material spliced in at @
  bool self_collision;    // what the shipped file asks for
};

std::string cs184Text(const Cs184Case& c) {
  std::string text = c.published;
  text.replace(text.find('@'), 1, kCs184Material);
  return text;
}

void PrintTo(const Cs184Case& c, std::ostream* os) {
  *os << c.name;
}

class Cs184Scene : public testing::TestWithParam<Cs184Case> {};

TEST_P(Cs184Scene, LoadsToWhatTheCourseFileLoadsTo) {
  const Cs184Case& c = GetParam();
  const Scene ours = loadScene(kScenesDir / (c.name + ".json"));
  const Scene course = parseScene(cs184Text(c), "cs184/" + c.name + ".json");
  const ClothSpec &a = ours.cloth, &b = course.cloth;
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.num_width_points, b.num_width_points);
  EXPECT_EQ(a.num_height_points, b.num_height_points);
  EXPECT_EQ(a.thickness, b.thickness);
  EXPECT_EQ(a.orientation, b.orientation);
  EXPECT_EQ(a.pinned, b.pinned);
  EXPECT_EQ(a.enable_structural, b.enable_structural);
  EXPECT_EQ(a.enable_shearing, b.enable_shearing);
  EXPECT_EQ(a.enable_bending, b.enable_bending);
  EXPECT_EQ(a.damping, b.damping);
  EXPECT_EQ(a.density, b.density);
  EXPECT_EQ(a.ks, b.ks);
  ASSERT_EQ(ours.spheres.size(), course.spheres.size());
  for (std::size_t i = 0; i < ours.spheres.size(); ++i) {
    EXPECT_EQ(ours.spheres[i].origin, course.spheres[i].origin);
    EXPECT_EQ(ours.spheres[i].radius, course.spheres[i].radius);
    EXPECT_EQ(ours.spheres[i].friction, course.spheres[i].friction);
  }
  ASSERT_EQ(ours.planes.size(), course.planes.size());
  for (std::size_t i = 0; i < ours.planes.size(); ++i) {
    EXPECT_EQ(ours.planes[i].point, course.planes[i].point);
    EXPECT_EQ(ours.planes[i].normal, course.planes[i].normal);
    EXPECT_EQ(ours.planes[i].friction, course.planes[i].friction);
  }
  // CS184 steps 30 substeps per frame at 90 frames per second, and always runs self-collision.
  EXPECT_EQ(ours.sim.frames_per_sec, 90.0);
  EXPECT_EQ(ours.sim.steps_per_frame, 30);
  EXPECT_TRUE(course.sim.self_collision);
  EXPECT_EQ(ours.sim.self_collision, c.self_collision);
  EXPECT_EQ(ours.sim.gravity, course.sim.gravity);
  EXPECT_EQ(ours.sim.stretch_passes, course.sim.stretch_passes);
  EXPECT_EQ(ours.sim.stretch_limit, course.sim.stretch_limit);
  EXPECT_FALSE(ours.sim.wind.enabled);
}

// clang-format off
INSTANTIATE_TEST_SUITE_P(Scenes, Cs184Scene, testing::Values(
    Cs184Case{"pinned2", R"({"cloth": {@, "orientation": 0, "pinned": [[0, 0], [49, 0]]}})", false},
    Cs184Case{"pinned4", R"({"cloth": {@, "orientation": 0, "pinned": [[0, 0], [0, 49], [49, 0], [49, 49]]}})", false},
    Cs184Case{"sphere", R"({"sphere": {"origin": [0.5, 0.2, 0.5], "radius": 0.2, "friction": 0.3},
                            "cloth": {@, "orientation": 0}})", true},
    Cs184Case{"plane", R"({"plane": {"point": [0, 0, 0], "normal": [0, 1, 0], "friction": 0.5},
                           "cloth": {@, "orientation": 0}})", true},
    Cs184Case{"selfCollision", R"({"plane": {"point": [0, 0, 0], "normal": [0, 1, 0], "friction": 0.5},
                                   "cloth": {@, "orientation": 1}})", true}),
  [](const testing::TestParamInfo<Cs184Case>& p) { return p.param.name; });
// clang-format on

// What each scene is for, as its name says, from the positions it starts in: pinned2 hangs from two
// corners of one edge, pinned4 from all four; the sphere lies under the middle of the falling cloth;
// the plane is under the cloth; the vertical cloth stands on the plane.
TEST(Cs184Scenes, EachSceneSetsUpWhatItsNameSays) {
  auto load = [](const char* name) { return loadScene(kScenesDir / name); };
  const Scene sphere = load("sphere.json");
  ASSERT_EQ(sphere.spheres.size(), 1u);
  const SphereSpec& ball = sphere.spheres[0];
  EXPECT_EQ(ball.origin.x, sphere.cloth.width / 2);
  EXPECT_EQ(ball.origin.z, sphere.cloth.height / 2);
  EXPECT_LT(ball.origin.y + ball.radius, 1.0) << "the horizontal cloth starts at y = 1, above the sphere";

  for (const char* name : {"plane.json", "selfCollision.json"}) {
    const Scene s = load(name);
    ASSERT_EQ(s.planes.size(), 1u) << name;
    EXPECT_EQ(s.planes[0].normal, glm::dvec3(0, 1, 0)) << name;
    EXPECT_EQ(s.planes[0].point.y, 0.0) << name << ": the floor, y = 0";
  }
  const Scene standing = load("selfCollision.json");
  EXPECT_EQ(standing.cloth.orientation, Orientation::Vertical) << "its bottom row starts on the floor";
  EXPECT_TRUE(standing.cloth.pinned.empty());

  const Scene two = load("pinned2.json"), four = load("pinned4.json");
  const int last = two.cloth.num_width_points - 1;
  EXPECT_EQ(two.cloth.pinned, (std::vector<glm::ivec2>{{0, 0}, {last, 0}}));
  EXPECT_EQ(four.cloth.pinned.size(), 4u);
  for (const glm::ivec2 p : four.cloth.pinned) {
    EXPECT_TRUE(p.x == 0 || p.x == four.cloth.num_width_points - 1) << "a corner";
    EXPECT_TRUE(p.y == 0 || p.y == four.cloth.num_height_points - 1) << "a corner";
  }
}

TEST(ExtensionScenes, WindIsAVerticalClothPinnedAlongItsTopEdgeInTurbulentWind) {
  Scene scene = loadScene(kScenesDir / "wind.json");
  EXPECT_EQ(scene.cloth.orientation, Orientation::Vertical);
  std::vector<glm::ivec2> top_edge;
  for (int x = 0; x < scene.cloth.num_width_points; ++x)
    top_edge.emplace_back(x, scene.cloth.num_height_points - 1);
  EXPECT_EQ(scene.cloth.pinned, top_edge);
  EXPECT_TRUE(scene.sim.wind.enabled);
  EXPECT_GT(glm::length(scene.sim.wind.velocity), 0.0);
  EXPECT_GT(scene.sim.wind.turbulence, 0.0);
  EXPECT_FALSE(scene.sim.self_collision);
}

TEST(ExtensionScenes, TwoSpheresUsesTheListKeys) {
  Scene scene = loadScene(kScenesDir / "two_spheres.json");
  EXPECT_EQ(scene.spheres.size(), 2u);
  EXPECT_EQ(scene.planes.size(), 1u);
}

// ---------------------------------------------------------------------------------------------------
TEST(SceneDefaults, Cs184FileWithoutSimulationRunsSelfCollisionAndDefaultTiming) {
  Scene scene = parseScene("{" + kCloth + "}", "cs184.json");
  const SimParams defaults;
  EXPECT_TRUE(scene.sim.self_collision);
  EXPECT_EQ(scene.sim.frames_per_sec, defaults.frames_per_sec);
  EXPECT_EQ(scene.sim.steps_per_frame, defaults.steps_per_frame);
  EXPECT_EQ(scene.sim.gravity, defaults.gravity);
  EXPECT_EQ(scene.sim.stretch_passes, defaults.stretch_passes);
  EXPECT_EQ(scene.sim.stretch_limit, defaults.stretch_limit);
  EXPECT_EQ(scene.sim.integrator, Integrator::Verlet);  // CS184's integrator unless a scene asks
  EXPECT_EQ(scene.sim.iterations, 1);
  EXPECT_FALSE(scene.sim.wind.enabled);
  EXPECT_TRUE(scene.spheres.empty());
  EXPECT_TRUE(scene.planes.empty());
  EXPECT_EQ(scene.path, "cs184.json");
}

TEST(SceneDefaults, OptionalClothKeysTakeTheStructDefaults) {
  Scene scene = parseScene("{" + kCloth + "}", "minimal.json");
  const ClothSpec defaults;
  const ClothSpec& c = scene.cloth;
  EXPECT_EQ(c.width, 1.0);
  EXPECT_EQ(c.num_width_points, 4);
  EXPECT_EQ(c.num_height_points, 3);
  EXPECT_EQ(c.thickness, 0.01);
  EXPECT_EQ(c.orientation, Orientation::Horizontal);
  EXPECT_TRUE(c.pinned.empty());
  EXPECT_EQ(c.enable_structural, defaults.enable_structural);
  EXPECT_EQ(c.enable_shearing, defaults.enable_shearing);
  EXPECT_EQ(c.enable_bending, defaults.enable_bending);
  EXPECT_EQ(c.damping, defaults.damping);
  EXPECT_EQ(c.density, defaults.density);
  EXPECT_EQ(c.ks, defaults.ks);
}

TEST(SceneDefaults, ColliderFrictionDefaults) {
  Scene scene = parseScene("{" + kCloth +
                               R"(, "sphere": {"origin": [1, 2, 3], "radius": 0.5},
                                    "plane": {"point": [0, 1, 0], "normal": [0, 1, 0]}})",
                           "colliders.json");
  ASSERT_EQ(scene.spheres.size(), 1u);
  ASSERT_EQ(scene.planes.size(), 1u);
  EXPECT_EQ(scene.spheres[0].origin, glm::dvec3(1, 2, 3));
  EXPECT_EQ(scene.spheres[0].radius, 0.5);
  EXPECT_EQ(scene.spheres[0].friction, SphereSpec{}.friction);
  EXPECT_EQ(scene.planes[0].friction, PlaneSpec{}.friction);
}

TEST(SceneDefaults, WindSectionEnablesWindWithDefaultsUnlessDisabled) {
  const WindSpec defaults;
  Scene on = parseScene("{" + kCloth + R"(, "simulation": {"wind": {}}})", "wind_on.json");
  EXPECT_TRUE(on.sim.wind.enabled);
  EXPECT_EQ(on.sim.wind.velocity, defaults.velocity);
  EXPECT_EQ(on.sim.wind.turbulence, defaults.turbulence);
  EXPECT_EQ(on.sim.wind.noise_scale, defaults.noise_scale);
  EXPECT_EQ(on.sim.wind.noise_speed, defaults.noise_speed);
  EXPECT_EQ(on.sim.wind.drag, defaults.drag);
  Scene off = parseScene("{" + kCloth + R"(, "simulation": {"wind": {"enabled": false, "velocity": [3, 0, 0]}}})",
                         "wind_off.json");
  EXPECT_FALSE(off.sim.wind.enabled);
  EXPECT_EQ(off.sim.wind.velocity, glm::dvec3(3, 0, 0));
}

TEST(SceneValues, EveryKeyOfTheFullSceneIsRead) {
  Scene scene = parseScene(fullScene().dump(), "full.json");
  EXPECT_EQ(scene.cloth.pinned, (std::vector<glm::ivec2>{{0, 0}, {3, 2}}));
  EXPECT_EQ(scene.cloth.ks, 5000.0);
  EXPECT_EQ(scene.sim.wind.velocity, glm::dvec3(1, 0, 0));
  EXPECT_EQ(scene.sim.wind.turbulence, 0.1);
  EXPECT_EQ(scene.sim.gravity, glm::dvec3(0, -9.8, 0));
  EXPECT_EQ(scene.sim.stretch_limit, 1.1);
  EXPECT_DOUBLE_EQ(scene.sim.dt(), 1.0 / 2700.0);
}

TEST(SceneValues, IntegratorAndIterationsAreRead) {
  const Scene scene =
      parseScene("{" + kCloth + R"(, "simulation": {"integrator": "xpbd", "iterations": 4}})", "xpbd.json");
  EXPECT_EQ(scene.sim.integrator, Integrator::Xpbd);
  EXPECT_EQ(scene.sim.iterations, 4);
  const Scene verlet = parseScene("{" + kCloth + R"(, "simulation": {"integrator": "verlet"}})", "verlet.json");
  EXPECT_EQ(verlet.sim.integrator, Integrator::Verlet);
  EXPECT_FALSE(verlet.sim.tethers);  // CS184 has none
  EXPECT_TRUE(parseScene("{" + kCloth + R"(, "simulation": {"tethers": true}})", "t.json").sim.tethers);
}

TEST(SceneValues, SingleAndListCollidersCombineSingleFirst) {
  Scene scene = parseScene(fullScene().dump(), "full.json");
  ASSERT_EQ(scene.spheres.size(), 2u);
  EXPECT_EQ(scene.spheres[0].radius, 0.2);  // "sphere"
  EXPECT_EQ(scene.spheres[1].radius, 0.1);  // "spheres"[0]
  ASSERT_EQ(scene.planes.size(), 2u);
  EXPECT_EQ(scene.planes[0].friction, 0.5);
  EXPECT_EQ(scene.planes[1].friction, 0.2);
}

TEST(SceneValues, NormalIsNormalised) {
  struct Row {
    glm::dvec3 given, unit;
  };
  const double h = std::sqrt(0.5);
  for (const Row& row : {Row{{0, 3, 4}, {0, 0.6, 0.8}}, Row{{0, -2, 0}, {0, -1, 0}}, Row{{1e-200, 0, 0}, {1, 0, 0}},
                         Row{{1e200, 1e200, 0}, {h, h, 0}}}) {
    nlohmann::json scene = fullScene();
    scene["plane"]["normal"] = {row.given.x, row.given.y, row.given.z};
    glm::dvec3 n = parseScene(scene.dump(), "normal.json").planes[0].normal;
    EXPECT_NEAR(glm::length(n), 1.0, 1e-15);
    EXPECT_NEAR(glm::length(n - row.unit), 0.0, 1e-15) << row.given.x << " " << row.given.y << " " << row.given.z;
  }
}

// CS184's loader converts 50.0 to an int; a file that relies on this must still load.
TEST(SceneValues, IntegralFloatsAreIntegers) {
  nlohmann::json scene = fullScene();
  scene["cloth"]["num_width_points"] = 4.0;
  scene["cloth"]["orientation"] = 1.0;
  scene["cloth"]["pinned"] = {{3.0, 2.0}};
  Scene s = parseScene(scene.dump(), "floats.json");
  EXPECT_EQ(s.cloth.num_width_points, 4);
  EXPECT_EQ(s.cloth.orientation, Orientation::Vertical);
  EXPECT_EQ(s.cloth.pinned, (std::vector<glm::ivec2>{{3, 2}}));
}

TEST(SceneValues, LargestGridIsAccepted) {
  nlohmann::json scene = fullScene();
  scene["cloth"]["num_width_points"] = 2048;
  scene["cloth"]["num_height_points"] = 2048;
  scene["cloth"]["thickness"] = 0.0002;  // self-collision's bound (SceneLimits below): 2 neighbours a point
  EXPECT_EQ(parseScene(scene.dump(), "large.json").cloth.pointCount(), kMaxClothPoints);
}

TEST(SceneValues, LargestCountsAndSmallestFloatsAreAccepted) {
  nlohmann::json scene = fullScene();
  scene["simulation"]["steps_per_frame"] = kMaxStepsPerFrame;
  scene["simulation"]["stretch_passes"] = kMaxStretchPasses;
  scene["cloth"]["thickness"] = 1.2e-38;
  scene["simulation"]["wind"]["noise_scale"] = 1.2e-38;
  const Scene s = parseScene(scene.dump(), "edges.json");
  EXPECT_EQ(s.sim.steps_per_frame, kMaxStepsPerFrame);
  EXPECT_EQ(s.sim.stretch_passes, kMaxStretchPasses);
  EXPECT_GT(float(s.cloth.thickness), 0.0f);
}

// Each count is checked before the work it would cost: the meshes below do not exist, and the count is
// what is refused.
TEST(SceneLimits, CollidersAreCountedBeforeAnyIsRead) {
  std::string meshes, spheres;
  for (int i = 0; i <= kMaxMeshes; ++i)
    meshes += std::string(i ? ", " : "") + R"({"obj": "no_such_mesh.obj"})";
  expectRejected("{" + kCloth + R"(, "meshes": [)" + meshes + "]}", "m.json", "meshes",
                 "17 meshes, more than the 16 a scene may have");
  for (int i = 0; i < kMaxSpheres; ++i)
    spheres += std::string(i ? ", " : "") + R"({"origin": [0, 0, 0], "radius": 1})";
  EXPECT_EQ(parseScene("{" + kCloth + R"(, "spheres": [)" + spheres + "]}", "s.json").spheres.size(), 256u);
  expectRejected("{" + kCloth + R"(, "sphere": {"origin": [0, 0, 0], "radius": 1}, "spheres": [)" + spheres + "]}",
                 "s.json", "spheres", "257 spheres, more than the 256 a scene may have");
}

std::string grid(int n, double thickness, bool self_collision = true) {
  return R"({"cloth": {"width": 1, "height": 1, "num_width_points": )" + std::to_string(n) +
         R"(, "num_height_points": )" + std::to_string(n) + R"(, "thickness": )" + std::to_string(thickness) +
         R"(, "orientation": 0}, "simulation": {"self_collision": )" + (self_collision ? "true" : "false") + "}}";
}

// A thickness large against the spacing made self-collision compare nearly every pair (29 s a frame).
TEST(SceneLimits, SelfCollisionNeighboursAndPairsAreBounded) {
  expectRejected(grid(50, 0.5), "t.json", "cloth.thickness",
                 "self-collision would compare each point with about 7543 others within 2 x thickness (at most 1024)");
  EXPECT_NO_THROW(parseScene(grid(50, 0.5, false), "t.json")) << "without self-collision the thickness is free";
  EXPECT_NO_THROW(parseScene(grid(512, 0.0095), "t.json")) << "a CS184 scene refined to 512^2: about 300 a point";
  expectRejected(grid(2048, 0.0014), "t.json", "cloth.thickness", "pairs within 2 x thickness (at most 134217728)");
}

std::string loadError(const std::string& path) {
  try {
    loadScene(path);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "loaded";
}

TEST(SceneFiles, ADeviceIsRefusedBeforeAnyRead) {
  // /dev/zero never ends: it is not read at all.
  EXPECT_EQ(loadError("/dev/zero"), "/dev/zero: cannot open: is a device, not a file");
}

// A pipe's size is not known before: it is read one byte past the limit and no further.
TEST(SceneFiles, APipeBeyondTheSizeLimitIsRefusedAfterTheLimit) {
  int ends[2];
  ASSERT_EQ(::pipe(ends), 0);
  std::thread writer([&] {
    const std::string block(1 << 16, ' ');
    for (long long sent = 0; sent <= kMaxSceneBytes + (1 << 20);) {
      const ssize_t n = ::write(ends[1], block.data(), block.size());
      if (n <= 0) break;
      sent += n;
    }
    ::close(ends[1]);
  });
  const std::string path = "/proc/self/fd/" + std::to_string(ends[0]);
  EXPECT_EQ(loadError(path), path + ": too large for a scene (more than 16 MiB)");
  char rest[1 << 16];
  while (::read(ends[0], rest, sizeof rest) > 0) {
  }
  writer.join();
  ::close(ends[0]);
}

TEST(SceneFiles, AFifoWithNoWriterIsRefusedWithoutWaiting) {
  const fs::path fifo = fs::temp_directory_path() / ("drape_scene_fifo_" + std::to_string(::getpid()));
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(loadError(fifo.string()), fifo.string() + ": cannot read: a FIFO with nothing written to it");
  fs::remove(fifo);
}

}  // namespace
}  // namespace drape
