// `drape simulate --export`: the OBJ sequence read back with tinyobjloader, the binary PLY and the USDA
// file checked structurally, each with the same points as --out writes; bad export options are status 2
// before any work.
#include "shell_quote.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <tiny_obj_loader.h>
#include <unistd.h>
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

fs::path tempDir() {
  fs::path dir = fs::temp_directory_path() / ("drape_export_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

int run(const std::string& args) {
  const std::string cmd = std::string(DRAPE_BINARY) + " " + args + " >/dev/null 2>" + (tempDir() / "err").string();
  const int raw = std::system(cmd.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : 128;
}

const std::string kScene = std::string(DRAPE_SOURCE_DIR) + "/scenes/pinned2.json";
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
  EXPECT_NE(usda.find("endTimeCode = 6\n"), std::string::npos);
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

  // Exactly the samples 0, 3, 6, once each; the last holds --out's points.
  const std::size_t samples = usda.find("point3f[] points.timeSamples = {");
  ASSERT_NE(samples, std::string::npos);
  const std::regex sample_key("\n        (\\d+): \\[");
  std::vector<int> keys;
  for (auto it = std::sregex_iterator(usda.begin() + std::ptrdiff_t(samples), usda.end(), sample_key);
       it != std::sregex_iterator(); ++it)
    keys.push_back(std::stoi((*it)[1]));
  EXPECT_EQ(keys, (std::vector<int>{0, 3, 6}));
  const std::size_t last = usda.find("\n        6: [", samples);
  const std::string points = usda.substr(last + 13, usda.find(']', last + 13) - last - 13);
  std::vector<double> values;
  const std::regex number("-?[0-9.]+(e[-+]?[0-9]+)?");
  for (auto it = std::sregex_iterator(points.begin(), points.end(), number); it != std::sregex_iterator(); ++it)
    values.push_back(std::stod(it->str()));
  EXPECT_EQ(values, outPoints(dir_ / "out.json"));
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
  EXPECT_EQ(run(simulate("--export " + drape::testing::quote((dir_ / "missing" / "cloth.usda").string()))), 2);
  fs::create_directories(dir_ / "cloth.usda");
  EXPECT_EQ(run(simulate("--export " + drape::testing::quote((dir_ / "cloth.usda").string()))), 2);
  EXPECT_FALSE(fs::exists(dir_ / "out.json")) << "checked before the run";
  // --format wins over the extension.
  EXPECT_EQ(run(simulate("--export " + drape::testing::quote((dir_ / "seq.txt").string()) + " --format obj")), 0);
  EXPECT_TRUE(fs::exists(dir_ / "seq_0006.txt"));
}

}  // namespace
