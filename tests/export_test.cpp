// `drape simulate --export`: the OBJ sequence read back with tinyobjloader, the binary PLY and the USDA
// file checked structurally, each with the same points as --out writes; bad export options are status 2
// before any work.
#include "shell_quote.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <tiny_obj_loader.h>
#include <unistd.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path& tempDir() {
  static const drape::test::TempDir dir("drape_export_test_");
  return dir.path();
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

int run(const std::string& args) {
  const std::string cmd =
      std::string(drape::test::drapeBinary()) + " " + args + " >/dev/null 2>" + (tempDir() / "err").string();
  const int raw = std::system(cmd.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : 128;
}

const std::string kScene = std::string(drape::test::sourceDir()) + "/scenes/pinned2.json";
constexpr std::size_t kPoints = 50 * 50, kTriangles = 49 * 49 * 2;

// --out's points, as doubles parsed from its text.
std::vector<double> outPoints(const fs::path& file) {
  std::vector<double> flat;
  for (const auto& p : nlohmann::json::parse(slurp(file)))
    for (const auto& c : p)
      flat.push_back(c.get<double>());
  return flat;
}

class Export : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = tempDir() / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  std::string simulate(const std::string& export_args) {
    return "simulate " + drape::testing::quote(kScene) + " --frames 6 --every 3 --out " +
           drape::testing::quote((dir_ / "out.json").string()) + " " + export_args;
  }
  fs::path dir_;
};

TEST_F(Export, ObjSequenceReadsBackWithTheOutPoints) {
  ASSERT_EQ(run(simulate("--export " + drape::testing::quote((dir_ / "cloth.obj").string()))), 0);
  for (int frame : {0, 3, 6})
    EXPECT_TRUE(fs::exists(dir_ / ("cloth_000" + std::to_string(frame) + ".obj"))) << frame;
  for (int frame : {1, 2, 4, 5})
    EXPECT_FALSE(fs::exists(dir_ / ("cloth_000" + std::to_string(frame) + ".obj"))) << frame;

  tinyobj::ObjReader reader;
  ASSERT_TRUE(reader.ParseFromFile((dir_ / "cloth_0006.obj").string())) << reader.Error();
  const tinyobj::attrib_t& a = reader.GetAttrib();
  const std::vector<double> out = outPoints(dir_ / "out.json");
  ASSERT_EQ(a.vertices.size(), 3 * kPoints);
  // tinyobjloader's own number parser may land a double one ulp from strtod's; the points are floats.
  for (std::size_t k = 0; k < out.size(); ++k)
    ASSERT_EQ(float(a.vertices[k]), float(out[k])) << "coordinate " << k;
  EXPECT_EQ(a.normals.size(), 3 * kPoints);
  EXPECT_EQ(a.texcoords.size(), 2 * kPoints);
  ASSERT_EQ(reader.GetShapes().size(), 1u);
  const tinyobj::mesh_t& mesh = reader.GetShapes()[0].mesh;
  ASSERT_EQ(mesh.num_face_vertices.size(), kTriangles);
  for (const tinyobj::index_t& i : mesh.indices) {
    EXPECT_EQ(i.vertex_index, i.normal_index);
    EXPECT_EQ(i.vertex_index, i.texcoord_index);
  }
  // Unit normals; pinned2 hangs in front of +y at the start, so frame 0's point up.
  tinyobj::ObjReader first;
  ASSERT_TRUE(first.ParseFromFile((dir_ / "cloth_0000.obj").string()));
  for (std::size_t i = 0; i < kPoints; ++i)
    EXPECT_NEAR(first.GetAttrib().normals[3 * i + 1], 1.0, 1e-6);
}

TEST_F(Export, UsdaHasOneMeshWithTimeSampledPointsAtTheSceneFrameRate) {
  ASSERT_EQ(run(simulate("--export " + drape::testing::quote((dir_ / "cloth.usda").string()))), 0);
  const std::string usda = slurp(dir_ / "cloth.usda");
  EXPECT_EQ(usda.rfind("#usda 1.0\n", 0), 0u);
  EXPECT_NE(usda.find("timeCodesPerSecond = 90\n"), std::string::npos);
  EXPECT_NE(usda.find("startTimeCode = 0\n"), std::string::npos);
  EXPECT_TRUE(std::regex_search(usda, std::regex("\n    endTimeCode = 6 *\n")));
  EXPECT_NE(usda.find("defaultPrim = \"Cloth\""), std::string::npos);
  EXPECT_NE(usda.find("def Mesh \"Cloth\"\n{"), std::string::npos);
  // Brackets and braces balance: the file parses as nested lists.
  for (auto [open, close] : {std::pair{'[', ']'}, {'{', '}'}, {'(', ')'}})
    EXPECT_EQ(std::count(usda.begin(), usda.end(), open), std::count(usda.begin(), usda.end(), close)) << open;

  auto listAfter = [&](const std::string& key) {
    const std::size_t at = usda.find(key);
    EXPECT_NE(at, std::string::npos) << key;
    const std::size_t open = usda.find("= [", at) + 2, close = usda.find(']', open);
    return usda.substr(open + 1, close - open - 1);
  };
  const std::string counts = listAfter("int[] faceVertexCounts = ");
  EXPECT_EQ(std::size_t(std::count(counts.begin(), counts.end(), '3')), kTriangles);
  const std::string indices = listAfter("int[] faceVertexIndices = ");
  EXPECT_EQ(std::size_t(std::count(indices.begin(), indices.end(), ',')) + 1, 3 * kTriangles);
  const std::string uvs = listAfter("texCoord2f[] primvars:st = ");
  EXPECT_EQ(std::size_t(std::count(uvs.begin(), uvs.end(), '(')), kPoints);
  EXPECT_NE(usda.find("interpolation = \"vertex\""), std::string::npos);

  // Exactly the samples 0, 3, 6, once each, of the points, the normals and the extent; the last points are
  // --out's, the normals unit, the extent the points' box.
  const auto block = [&](const std::string& name) {
    const std::size_t open = usda.find(name + ".timeSamples = {");
    EXPECT_NE(open, std::string::npos) << name;
    return open == std::string::npos ? std::string() : usda.substr(open, usda.find("\n    }\n", open) - open);
  };
  const std::regex sample_key("\n        (\\d+): \\[");
  for (const char* name : {"point3f[] points", "normal3f[] normals", "float3[] extent"}) {
    const std::string samples = block(name);
    std::vector<int> keys;
    for (auto it = std::sregex_iterator(samples.begin(), samples.end(), sample_key); it != std::sregex_iterator(); ++it)
      keys.push_back(std::stoi((*it)[1]));
    EXPECT_EQ(keys, (std::vector<int>{0, 3, 6})) << name;
  }
  EXPECT_NE(usda.find("normal3f[] normals (\n        interpolation = \"vertex\"\n    )"), std::string::npos);
  const std::string normals = block("normal3f[] normals");
  EXPECT_EQ(std::size_t(std::count(normals.begin(), normals.end(), '(')), 3 * kPoints);
  const std::size_t samples = usda.find("point3f[] points.timeSamples = {");
  ASSERT_NE(samples, std::string::npos);
  const std::size_t last = usda.find("\n        6: [", samples);
  const std::string points = usda.substr(last + 13, usda.find(']', last + 13) - last - 13);
  std::vector<double> values;
  const std::regex number("-?[0-9.]+(e[-+]?[0-9]+)?");
  for (auto it = std::sregex_iterator(points.begin(), points.end(), number); it != std::sregex_iterator(); ++it)
    values.push_back(std::stod(it->str()));
  EXPECT_EQ(values, outPoints(dir_ / "out.json"));
  glm::dvec3 lo(1e9), hi(-1e9);
  for (std::size_t i = 0; i < values.size(); ++i) {
    lo[int(i % 3)] = std::min(lo[int(i % 3)], double(float(values[i])));
    hi[int(i % 3)] = std::max(hi[int(i % 3)], double(float(values[i])));
  }
  const std::string extent = block("float3[] extent");
  const std::string box = extent.substr(extent.find("6: [") + 4);
  std::vector<double> corners;
  for (auto it = std::sregex_iterator(box.begin(), box.end(), number); it != std::sregex_iterator(); ++it)
    corners.push_back(std::stod(it->str()));
  ASSERT_EQ(corners.size(), 6u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(float(corners[std::size_t(k)]), float(lo[k])) << k;
    EXPECT_EQ(float(corners[std::size_t(k) + 3]), float(hi[k])) << k;
  }
}

TEST_F(Export, PlyIsBinaryLittleEndianWithTheOutPointsAsFloats) {
  ASSERT_EQ(run(simulate("--export " + drape::testing::quote((dir_ / "cloth.ply").string()))), 0);
  const std::string ply = slurp(dir_ / "cloth_0006.ply");
  const std::string end = "end_header\n";
  const std::size_t body = ply.find(end) + end.size();
  EXPECT_EQ(ply.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
  EXPECT_NE(ply.find("element vertex 2500\n"), std::string::npos);
  EXPECT_NE(ply.find("element face 4802\n"), std::string::npos);
  ASSERT_EQ(ply.size(), body + kPoints * 8 * 4 + kTriangles * (1 + 3 * 4));
  const std::vector<double> out = outPoints(dir_ / "out.json");
  for (std::size_t i = 0; i < kPoints; ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      unsigned char bytes[4];
      std::memcpy(bytes, ply.data() + body + i * 32 + k * 4, 4);
      const std::uint32_t bits = std::uint32_t(bytes[0]) | std::uint32_t(bytes[1]) << 8 |
                                 std::uint32_t(bytes[2]) << 16 | std::uint32_t(bytes[3]) << 24;
      float v;
      std::memcpy(&v, &bits, 4);
      ASSERT_EQ(v, float(out[3 * i + k])) << "point " << i;
    }
  EXPECT_EQ(ply[body + kPoints * 32], char(3)) << "every face lists 3 corners";
}

TEST_F(Export, BadOptionsAreStatusTwoBeforeAnyWork) {
  EXPECT_EQ(run(simulate("--export " + drape::testing::quote((dir_ / "cloth.txt").string()))), 2);
  EXPECT_NE(slurp(tempDir() / "err").find("--export"), std::string::npos);
  EXPECT_EQ(run(simulate("--export " + drape::testing::quote((dir_ / "cloth.obj").string()) + " --format fbx")), 2);
  EXPECT_EQ(run(simulate("--export " + drape::testing::quote((dir_ / "cloth.ply").string()) + " --format obj")), 2);
  EXPECT_NE(slurp(tempDir() / "err").find("cloth.ply is ply, but --format says obj"), std::string::npos);
  std::ofstream(dir_ / "file") << "a file";
  EXPECT_EQ(run(simulate("--export " + drape::testing::quote((dir_ / "file" / "cloth.usda").string()))), 2);
  EXPECT_FALSE(fs::exists(dir_ / "out.json")) << "checked before the run";
}

// --format decides the extension; a folder gets numbered files inside it; missing folders are made.
TEST_F(Export, FormatFoldersAndMissingFolders) {
  const auto at = [&](const std::string& path) { return drape::testing::quote((dir_ / path).string()); };
  ASSERT_EQ(run(simulate("--export " + at("out/c") + " --format obj")), 0);
  for (const char* name : {"c_0000.obj", "c_0003.obj", "c_0006.obj"})
    EXPECT_TRUE(fs::exists(dir_ / "out" / name)) << name;
  ASSERT_EQ(run(simulate("--export " + at("seq.txt") + " --format ply")), 0);
  EXPECT_TRUE(fs::exists(dir_ / "seq.txt_0006.ply")) << "an extension that is no format's stays in the name";
  ASSERT_EQ(run(simulate("--export " + at("folder") + "/")), 0);
  EXPECT_TRUE(fs::exists(dir_ / "folder" / "cloth_0006.obj"));
  fs::create_directories(dir_ / "existing");
  ASSERT_EQ(run(simulate("--export " + at("existing") + " --format usda")), 0);
  EXPECT_TRUE(fs::exists(dir_ / "existing" / "cloth.usda"));
  ASSERT_EQ(run(simulate("--export " + at("deep/er/cloth.usda"))), 0);
  EXPECT_TRUE(fs::exists(dir_ / "deep" / "er" / "cloth.usda"));
}

// A run that blows up keeps its USD file up to the last good frame, its header saying so, and says so.
TEST_F(Export, ABlowUpKeepsTheUsdaUpToTheLastGoodFrame) {
  // Stiff for one substep a frame: a spring passes 11 times its rest length at frame 22.
  std::ofstream(dir_ / "blows.json")
      << R"({"cloth": {"width": 1, "height": 1, "num_width_points": 12, "num_height_points": 12, "thickness": 0.0095,
             "orientation": 0, "pinned": [[0, 0], [11, 0]], "damping": 0, "density": 150.0, "ks": 5000.0},
             "simulation": {"self_collision": false, "steps_per_frame": 1, "stretch_passes": 0}})";
  const std::string cmd = "simulate " + drape::testing::quote((dir_ / "blows.json").string()) +
                          " --frames 60 --export " + drape::testing::quote((dir_ / "b.usda").string());
  ASSERT_EQ(run(cmd), 4);
  const std::string err = slurp(tempDir() / "err");
  const std::smatch m = [&] {
    std::smatch match;
    std::regex_search(err, match, std::regex("blew up at frame (\\d+).*--export keeps frames 0 to (\\d+)"));
    return match;
  }();
  ASSERT_EQ(m.size(), 3u) << err;
  const int last = std::stoi(m[2]);
  EXPECT_EQ(last, std::stoi(m[1]) - 1);
  const std::string usda = slurp(dir_ / "b.usda");
  EXPECT_TRUE(std::regex_search(usda, std::regex("\n    endTimeCode = " + std::to_string(last) + " *\n")));
  EXPECT_NE(usda.find("\n        " + std::to_string(last) + ": ["), std::string::npos);
  EXPECT_EQ(usda.find("\n        " + std::to_string(last + 1) + ": ["), std::string::npos);
  EXPECT_EQ(usda.substr(usda.size() - 2), "}\n") << "a whole file";
}

}  // namespace
