// The OBJ reader's one grammar and its limits, and the input files it opens: each refusal names the line
// and the problem, each limit is hit while the file is read (not after), and no file makes it wait.
#include "core/obj_reader.hpp"
#include "core/input_file.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace drape {
namespace {

namespace fs = std::filesystem;

const ObjLimits kLimits{1000, " (the test's limit)"};
const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 0 1\n";

const fs::path& tempDir() {
  static const test::TempDir dir("drape_obj_test_");
  return dir.path();
}

std::string refusal(const std::string& text, const ObjLimits& limits = kLimits) {
  try {
    parseObj(text, limits);
  } catch (const MeshError& e) {
    return e.what();
  }
  return "accepted";
}

std::string refusalOfFile(const fs::path& file) {
  try {
    readObj(file, kLimits);
  } catch (const MeshError& e) {
    return e.what();
  }
  return "accepted";
}

struct BadLine {
  const char* name;
  std::string text;
  std::string expect;
};

void PrintTo(const BadLine& b, std::ostream* os) {
  *os << b.name;
}

class ObjGrammar : public ::testing::TestWithParam<BadLine> {};

TEST_P(ObjGrammar, RefusesWithTheLineAndOneLine) {
  const std::string what = refusal(GetParam().text);
  EXPECT_NE(what.find(GetParam().expect), std::string::npos) << what;
  EXPECT_EQ(what.find('\n'), std::string::npos) << what;
}

// Every coordinate through the same grammar, whatever separates the words: tinyobjloader read these as 0.
INSTANTIATE_TEST_SUITE_P(
    Obj, ObjGrammar,
    ::testing::Values(
        BadLine{"tab_nan", "v 0 0 0\nv\tnan 0 0\n", "line 2: vertex coordinate 'nan' is not a finite number"},
        BadLine{"tab_inf", "v\tinf 0 0\n", "line 1: vertex coordinate 'inf' is not a finite number"},
        BadLine{"tab_word", "v\tabc 0 0\n", "line 1: vertex coordinate 'abc' is not a number"},
        BadLine{"hex", "v 0x10 0 0\n", "line 1: vertex coordinate '0x10' is not a number"},
        BadLine{"trailing_letter", "v 1 2 3z\n", "line 1: vertex coordinate '3z' is not a number"},
        BadLine{"comma_decimal", "v 1,5 2 3\n", "'1,5' is not a number"},
        BadLine{"signed_infinity", "v -Infinity 0 0\n", "'-Infinity' is not a finite number"},
        BadLine{"overflow", "v 1e999 0 0\n", "'1e999' is not a finite number"},
        BadLine{"control_bytes", std::string("v 1\x01\xff 0 0\n"), "'1\\x01\\xff' is not a number"},
        BadLine{"two_numbers", "v 0 0\n", "line 1: a vertex needs x, y and z"},
        BadLine{"five_numbers", "v 0 0 0 1 1\n", "this one has 5 numbers"},
        BadLine{"eight_numbers", "v 0 0 0 1 1 1 1 1\n", "too many numbers"},
        BadLine{"texcoord_nan", kTriangle + "vt nan 0\n", "line 4: texture coordinate 'nan' is not a finite number"},
        BadLine{"normal_word", kTriangle + "vn 0 x 1\n", "line 4: normal coordinate 'x' is not a number"},
        BadLine{"index_beyond_int", kTriangle + "f 1 2 99999999999\n",
                "line 4: face corner '99999999999' names vertex 99999999999, but only 3 come before this line"},
        BadLine{"index_zero", kTriangle + "f 1 2 0\n", "line 4: face corner '0' names vertex 0 (OBJ counts from 1)"},
        BadLine{"index_back_too_far", kTriangle + "f -1 -2 -4\n", "names vertex -4, but only 3 come before"},
        BadLine{"index_forward", "v 0 0 0\nf 1 2 3\nv 1 0 0\nv 0 0 1\n", "line 2: face corner '2' names vertex 2"},
        BadLine{"index_word", kTriangle + "f 1 2 3a\n", "face corner '3a' is not v, v/vt, v//vn or v/vt/vn"},
        BadLine{"index_slashes", kTriangle + "f 1/ 2 3\n", "face corner '1/' is not v"},
        BadLine{"texcoord_missing", kTriangle + "f 1/1 2/1 3/1\n", "names texture coordinate 1, but none come"},
        BadLine{"normal_missing", kTriangle + "vn 0 1 0\nf 1//1 2//2 3//1\n", "names normal 2, but only 1 come"},
        BadLine{"empty_face", kTriangle + "f\n", "line 4: a face needs corners"},
        BadLine{"no_faces", kTriangle, "no faces"}),
    [](const ::testing::TestParamInfo<BadLine>& p) { return std::string(p.param.name); });

TEST(ObjReader, ReadsEveryNumberFormAndSeparatorWritersUse) {
  const PolygonMesh m = parseObj(
      "# comment\r\nv\t1\t-2.5e-1  +.5\r\nv 1. 2E+1 -0 # a comment\nv 1e-400 0 0\n"
      "o name\ng group\ns off\nusemtl red\nvt 0.5 0.25\nvt 1\nvn 0 1 0\n"
      "f 1/1/1 2/2/1 -1/1/1\nl 1 2\n",
      kLimits);
  ASSERT_EQ(m.positions.size(), 3u);
  EXPECT_EQ(m.positions[0], glm::dvec3(1, -0.25, 0.5));
  EXPECT_EQ(m.positions[1], glm::dvec3(1, 20, 0));
  EXPECT_EQ(m.positions[2], glm::dvec3(0, 0, 0)) << "an underflow is 0, not an error";
  ASSERT_EQ(m.faces.size(), 1u);
  EXPECT_EQ(m.faces[0], (std::vector<std::uint32_t>{0, 1, 2}));
  ASSERT_EQ(m.uvs.size(), 3u);
  EXPECT_EQ(m.uvs[0], glm::vec2(0.5f, 0.25f));
  EXPECT_EQ(m.uvs[1], glm::vec2(1.0f, 0.0f));
}

// tinyobjloader kept a face's corner count in 8 bits: 300 corners read as 44, the rest misread.
TEST(ObjReader, AFaceOfThreeHundredCornersKeepsThemAll) {
  std::string text, face = "f";
  for (int i = 0; i < 300; ++i) {
    text += "v " + std::to_string(std::cos(i * 0.0209)) + " 0 " + std::to_string(std::sin(i * 0.0209)) + "\n";
    face += " " + std::to_string(i + 1);
  }
  const PolygonMesh m = parseObj(text + face + "\n", kLimits);
  ASSERT_EQ(m.faces.size(), 1u);
  ASSERT_EQ(m.faces[0].size(), 300u);
  EXPECT_EQ(m.faces[0][299], 299u);
}

// The limit stops the reading at the line that passes it: the bad statement after it is never reached.
TEST(ObjReader, CountsAreLimitedWhileReading) {
  std::string vertices;
  for (int i = 0; i < 11; ++i)
    vertices += "v 0 0 " + std::to_string(i) + "\n";
  EXPECT_EQ(refusal(vertices + "v nan 0 0\n", {10, " (ten)"}), "line 11: more than 10 vertices (ten)");
  std::string faces = kTriangle;
  for (int i = 0; i < 23; ++i)
    faces += "f 1\n";  // one corner each: the faces' limit comes before the corners'
  EXPECT_EQ(refusal(faces + "v nan\n", {3, ""}), "line 26: more than 22 faces");
  std::string corners = kTriangle + "f";
  for (int i = 0; i < 100; ++i)
    corners += " 1";
  EXPECT_EQ(refusal(corners + "\n", {3, ""}), "line 4: more than 66 face corners in all");
}

TEST(ObjReader, ALineBeyondAMebibyteIsRefused) {
  const std::string what = refusal(kTriangle + "# " + std::string(kMaxObjLineBytes, 'x') + "\nf 1 2 3\n");
  EXPECT_EQ(what, "line 4: longer than 1 MiB (not an OBJ statement)");
  const fs::path file = tempDir() / "long_line.obj";
  std::ofstream(file) << kTriangle << std::string(3 * kMaxObjLineBytes, '1');
  EXPECT_EQ(refusalOfFile(file), "line 4: longer than 1 MiB (not an OBJ statement)");
}

TEST(ObjReader, ReadsAFileInPiecesAsItReadsText) {
  const fs::path file = tempDir() / "pieces.obj";
  std::string text;
  for (int i = 0; i < 60000; ++i)  // over a mebibyte: lines cross the reader's pieces
    text += "v " + std::to_string(i) + " 0.5 -1\n";
  text += "f 1 2 3\nf 4 5 6";  // no newline at the end
  std::ofstream(file) << text;
  const PolygonMesh m = readObj(file, {100000, ""});
  EXPECT_EQ(m.positions.size(), 60000u);
  EXPECT_EQ(m.positions[59999], glm::dvec3(59999, 0.5, -1));
  ASSERT_EQ(m.faces.size(), 2u);
  EXPECT_EQ(m.faces[1], (std::vector<std::uint32_t>{3, 4, 5}));
}

// The size limit before a byte is read: a sparse file claims 600 MiB and costs no disk.
TEST(ObjReader, AFileOverTheSizeLimitIsRefusedUnread) {
  const fs::path file = tempDir() / "huge.obj";
  { std::ofstream(file) << "v nan nan nan\n"; }
  fs::resize_file(file, 600LL << 20);
  EXPECT_EQ(refusalOfFile(file), "too large for an OBJ file (more than 512 MiB)");
}

TEST(ObjReader, DevicesFifosDirectoriesAndLinkLoopsAreNamedWithoutWaiting) {
  EXPECT_EQ(refusalOfFile("/dev/zero"), "cannot open: is a device, not a file");
  EXPECT_EQ(refusalOfFile(tempDir()), "cannot open: is a directory, not a file");
  EXPECT_EQ(refusalOfFile(tempDir() / "missing.obj"), "cannot open: no such file");
  const fs::path fifo = tempDir() / "fifo.obj";
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(refusalOfFile(fifo), "cannot read: a FIFO with nothing written to it") << "no writer: no wait";
  const fs::path loop = tempDir() / "loop.obj";
  fs::remove(loop);
  fs::create_symlink(loop.filename(), loop);
  EXPECT_EQ(refusalOfFile(loop), "cannot open: Too many levels of symbolic links");
}

TEST(ObjReader, FloatRangeIsStatedInFewDigits) {
  try {
    checkFloatRange({{0, 0, 0}, {1e39, 0, 0}});
    FAIL() << "accepted";
  } catch (const MeshError& e) {
    EXPECT_EQ(std::string(e.what()), "vertex 1 is beyond float range (|coordinate| at most 3.40282347e+38)");
  }
}

TEST(InputFile, ReadsUpToTheLimitAndNoFurther) {
  const fs::path file = tempDir() / "sixteen";
  std::ofstream(file) << std::string(16, 'x');
  EXPECT_EQ(readInputFile(file, 16, "a test file"), std::string(16, 'x'));
  try {
    readInputFile(file, 15, "a test file");
    FAIL() << "read past the limit";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "too large for a test file (more than 15 bytes)");
  }
  EXPECT_EQ(describeBytes(512LL << 20), "512 MiB");
  EXPECT_EQ(describeBytes(64 << 10), "64 KiB");
}

}  // namespace
}  // namespace drape
