// Base fixture of every *_gl_test: one headless GL 4.5 context per process, made lazily by the first
// test that needs it, with debug output on (a GL error fails the test). Without a context each test
// skips with the reason, or fails when DRAPE_REQUIRE_GL=1 (a machine that must run them).
#pragma once

#include "gl/context.hpp"
#include "gl/gl.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

namespace drape {

class GlTest : public ::testing::Test {
 public:
  static const gl::ContextInfo& info() { return shared().context->info(); }

  // A test shader under tests/glsl/.
  static std::filesystem::path testShader(const std::string& name) {
    return std::filesystem::path(drape::test::sourceDir()) / "tests" / "glsl" / name;
  }

 protected:
  void SetUp() override {
    const Shared& gl = shared();
    if (!gl.context) {
      const char* require = std::getenv("DRAPE_REQUIRE_GL");
      if (require && std::string(require) == "1") FAIL() << "DRAPE_REQUIRE_GL=1 but " << gl.failure;
      GTEST_SKIP() << "no OpenGL 4.5 context: " << gl.failure;
    }
    gl.context->makeCurrent();
    gl::takeDebugErrors();  // a previous test's leftovers are that test's failure, already reported
  }

  void TearDown() override {
    for (const std::string& error : gl::takeDebugErrors())
      ADD_FAILURE() << error;
  }

 private:
  struct Shared {
    std::optional<gl::HeadlessContext> context;
    std::string failure;
  };

  static const Shared& shared() {
    static const Shared instance = [] {
      Shared made;
      try {
        gl::HeadlessOptions options;
        options.debug = true;
        made.context = gl::HeadlessContext::create(options);
        std::printf("GL_RENDERER: %s (%s)\n", gl::describe(made.context->info()).c_str(),
                    made.context->info().platform.c_str());
      } catch (const gl::ContextError& e) {
        made.failure = e.what();
        std::printf("GL tests skip: %s\n", e.what());
      }
      std::fflush(stdout);
      return made;
    }();
    return instance;
  }
};

}  // namespace drape
