// Shader source assembly without GL: #version and defines, includes, include-once, errors with
// file:line, #line mapping back to every original line, and compiler-log translation.
#include "gl/shader_source.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

namespace drape {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> linesOf(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    lines.push_back(line);
  return lines;
}

std::size_t countOf(const std::string& text, const std::string& what) {
  std::size_t count = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
    ++count;
  return count;
}

// A scratch shader tree: <tmp>/glsl is the root, files are written on demand.
class ShaderSourceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("drape_shader_source_" + std::string(test->name()));
    fs::remove_all(dir_);
    fs::create_directories(root());
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path root() const { return dir_ / "glsl"; }
  fs::path write(const std::string& relative, const std::string& text) const {
    const fs::path path = root() / relative;
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
    return path;
  }

  fs::path dir_;
};

TEST_F(ShaderSourceTest, VersionComesFirstThenTheDefinesInOrder) {
  const fs::path main = write("sim/main.comp", "void main() {}\n");
  const gl::ShaderSource source = gl::preprocess(main, {{"NUM_SPHERES", "2"}, {"SELF_COLLISION", ""}}, root());
  const std::vector<std::string> lines = linesOf(source.text);
  ASSERT_GE(lines.size(), 4u);
  EXPECT_EQ(lines[0], "#version 450 core");
  EXPECT_EQ(lines[1], "#define NUM_SPHERES 2");
  EXPECT_EQ(lines[2], "#define SELF_COLLISION");
  EXPECT_EQ(countOf(source.text, "#version"), 1u);
}

TEST_F(ShaderSourceTest, IncludesResolveNextToTheFileThenUnderTheRoot) {
  write("shared/common.glsl", "float fromRoot;\n");
  write("sim/lib/helper.glsl", "float fromHelper;\n#include \"shared/common.glsl\"\n");
  write("sim/near.glsl", "float fromNear;\n");
  write("near.glsl", "float fromRootNear;\n");
  const fs::path main =
      write("sim/main.comp", "#include \"lib/helper.glsl\"\n  #  include \"near.glsl\"\nvoid main() {}\n");
  const gl::ShaderSource source = gl::preprocess(main, {}, root());
  const auto helper = source.text.find("float fromHelper;");
  const auto common = source.text.find("float fromRoot;");
  const auto near = source.text.find("float fromNear;");
  ASSERT_NE(helper, std::string::npos);
  ASSERT_NE(common, std::string::npos);
  ASSERT_NE(near, std::string::npos);
  EXPECT_LT(helper, common);
  EXPECT_LT(common, near);
  EXPECT_EQ(source.text.find("fromRootNear"), std::string::npos);  // the including file's directory wins
  EXPECT_EQ(source.text.find("#include"), std::string::npos);
  EXPECT_EQ(source.files.size(), 5u);  // preamble, main, helper, common, near
  EXPECT_EQ(source.paths.size(), source.files.size());
}

TEST_F(ShaderSourceTest, PragmaOnceIncludesAFileOnceAndOthersEveryTime) {
  write("once.glsl", "#pragma once\nfloat onceBody;\n");
  write("twice.glsl", "float twiceBody;\n");
  const fs::path main =
      write("main.comp",
            "#include \"once.glsl\"\n#include \"twice.glsl\"\n#include \"once.glsl\"\n#include \"twice.glsl\"\n");
  const gl::ShaderSource source = gl::preprocess(main, {}, root());
  EXPECT_EQ(countOf(source.text, "onceBody"), 1u);
  EXPECT_EQ(countOf(source.text, "twiceBody"), 2u);
  EXPECT_EQ(countOf(source.text, "#pragma once"), 0u);
}

TEST_F(ShaderSourceTest, IncludeCycleIsAnErrorAtTheIncludeThatClosesIt) {
  write("a.glsl", "float a;\n#include \"b.glsl\"\n");
  write("b.glsl", "float b;\n\n#include \"a.glsl\"\n");
  const fs::path main = write("main.comp", "#include \"a.glsl\"\n");
  try {
    gl::preprocess(main, {}, root());
    FAIL() << "an include cycle was accepted";
  } catch (const gl::ShaderError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(fs::path(e.file()).filename(), "b.glsl");
    EXPECT_NE(std::string(e.what()).find("include cycle"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("b.glsl:3: "), std::string::npos) << e.what();
  }
}

TEST_F(ShaderSourceTest, MissingIncludeNamesTheIncludingFileAndLine) {
  const fs::path main = write("sim/main.comp", "void f();\n\n#include \"nowhere.glsl\"\n");
  try {
    gl::preprocess(main, {}, root());
    FAIL() << "a missing include was accepted";
  } catch (const gl::ShaderError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("main.comp:3: cannot find include \"nowhere.glsl\""), std::string::npos)
        << e.what();
  }
}

TEST_F(ShaderSourceTest, VersionLinesBadDefinesAndMissingFilesAreRejected) {
  const fs::path versioned = write("v.comp", "\n#version 430\nvoid main() {}\n");
  try {
    gl::preprocess(versioned, {}, root());
    FAIL() << "#version in a shader file was accepted";
  } catch (const gl::ShaderError& e) {
    EXPECT_EQ(e.line(), 2);
  }
  const fs::path main = write("main.comp", "void main() {}\n");
  EXPECT_THROW(gl::preprocess(main, {{"BAD NAME", "1"}}, root()), gl::ShaderError);
  EXPECT_THROW(gl::preprocess(main, {{"1ST", "1"}}, root()), gl::ShaderError);
  EXPECT_THROW(gl::preprocess(main, {{"OK", "1\n2"}}, root()), gl::ShaderError);
  EXPECT_THROW(gl::preprocess(root() / "absent.comp", {}, root()), gl::ShaderError);
}

// Follows the #line directives as a GLSL 4.50 compiler does (the line after `#line N F` is line N of
// source string F) and checks that every line of every file is reported at its own file and number.
TEST_F(ShaderSourceTest, LineDirectivesMapEveryLineBackToItsFile) {
  write("shared/deep.glsl", "#pragma once\ndeep 1\n\ndeep 3\n");
  write("sim/helper.glsl",
        "helper 1\n#include \"shared/deep.glsl\"\nhelper 3\n#include \"shared/deep.glsl\"\nhelper 5\n");
  const fs::path main = write(
      "sim/main.comp", "main 1\n#include \"helper.glsl\"\nmain 3\n\r\n#include \"../shared/deep.glsl\"\nmain 6\n");
  const gl::ShaderSource source = gl::preprocess(main, {{"A", "1"}}, root());

  const std::regex directive(R"(^#line (\d+) (\d+)$)");
  std::map<std::string, std::map<int, std::string>> seen;  // file -> line -> text
  int string_number = 0, line_number = 1;
  for (const std::string& line : linesOf(source.text)) {
    std::smatch m;
    if (std::regex_match(line, m, directive)) {
      line_number = std::stoi(m[1]);
      string_number = std::stoi(m[2]);
      continue;
    }
    ASSERT_LT(string_number, static_cast<int>(source.files.size()));
    if (!line.empty()) seen[source.files[string_number]][line_number] = line;
    ++line_number;
  }
  const auto name = [&](const std::string& relative) { return gl::displayName(root() / relative); };
  EXPECT_EQ(seen[name("sim/main.comp")], (std::map<int, std::string>{{1, "main 1"}, {3, "main 3"}, {6, "main 6"}}));
  EXPECT_EQ(seen[name("sim/helper.glsl")],
            (std::map<int, std::string>{{1, "helper 1"}, {3, "helper 3"}, {5, "helper 5"}}));
  EXPECT_EQ(seen[name("shared/deep.glsl")], (std::map<int, std::string>{{2, "deep 1"}, {4, "deep 3"}}));
  EXPECT_EQ(countOf(source.text, "deep 1"), 1u);
  EXPECT_EQ(seen["<preamble>"].at(1), "#version 450 core");
}

TEST_F(ShaderSourceTest, CompilerLogsOfMesaNvidiaAndGlslangAreTranslated) {
  write("inc.glsl", "float x;\n");
  const fs::path main = write("sim/forces.comp", "#include \"../inc.glsl\"\n");
  const gl::ShaderSource source = gl::preprocess(main, {}, root());
  ASSERT_EQ(source.files.size(), 3u);
  const std::string forces = source.files[1];
  const std::string inc = source.files[2];
  EXPECT_EQ(fs::path(forces).filename(), "forces.comp");
  EXPECT_EQ(fs::path(inc).filename(), "inc.glsl");

  EXPECT_EQ(source.translateLog("1:12(3): error: syntax error, unexpected ';'\n"),
            forces + ":12:3: error: syntax error, unexpected ';'\n");
  EXPECT_EQ(source.translateLog("2(7) : error C0000: syntax error, unexpected ';'\n"),
            inc + ":7: error C0000: syntax error, unexpected ';'\n");
  EXPECT_EQ(source.translateLog("ERROR: 2:4: '' :  syntax error\nERROR: 1 compilation errors.  No code generated.\n"),
            inc + ":4: ERROR: '' :  syntax error\nERROR: 1 compilation errors.  No code generated.\n");
  EXPECT_EQ(source.translateLog("9:1(1): error: beyond the table\n"), "9:1(1): error: beyond the table\n");
  EXPECT_EQ(source.translateLog("warning: no location\r\n"), "warning: no location\n");

  EXPECT_EQ(source.firstLocation("some banner\n2(7) : error C0000: x\n1:3(1): error: y\n"), std::make_pair(inc, 7));
  EXPECT_EQ(source.firstLocation("nothing here\n"), std::make_pair(std::string(), 0));
}

TEST(ShaderSource, GlslRootIsTheRepositoryGlslUnlessOverridden) {
  const char* saved = std::getenv("DRAPE_GLSL_DIR");
  const std::string restore = saved ? saved : "";
  unsetenv("DRAPE_GLSL_DIR");
  EXPECT_EQ(gl::glslRoot(), fs::path(drape::test::sourceDir()) / "glsl");
  EXPECT_TRUE(fs::is_directory(gl::glslRoot()));
  setenv("DRAPE_GLSL_DIR", "/elsewhere/glsl", 1);
  EXPECT_EQ(gl::glslRoot(), fs::path("/elsewhere/glsl"));
  if (saved) {
    setenv("DRAPE_GLSL_DIR", restore.c_str(), 1);
  } else {
    unsetenv("DRAPE_GLSL_DIR");
  }
}

TEST(ShaderSource, DisplayNamesAreRelativeToTheSourceTree) {
  EXPECT_EQ(gl::displayName(fs::path(drape::test::sourceDir()) / "glsl" / "sim" / "forces.comp"),
            "glsl/sim/forces.comp");
  EXPECT_EQ(gl::displayName("/not/in/the/tree.comp"), "/not/in/the/tree.comp");
}

}  // namespace
}  // namespace drape
