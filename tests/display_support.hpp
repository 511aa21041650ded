// GLFW windows need an X display. Tests that make one start with RUN_WITH_DISPLAY(): without $DISPLAY
// the test runs itself again in a child process under `xvfb-run` and passes or fails with that run;
// without xvfb-run it is skipped with the reason.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

namespace drape::testing {

inline bool hasDisplay() {
  const char* display = std::getenv("DISPLAY");
  return display && *display;
}

// Runs the current test again under xvfb-run (screen 1280x1024); returns its exit status.
inline int rerunUnderXvfb() {
  char self[4096];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) return -1;
  self[n] = '\0';
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string command = std::string("xvfb-run -a -s '-screen 0 1280x1024x24' '") + self +
                              "' --gtest_filter=" + info->test_suite_name() + "." + info->name();
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace drape::testing

#define RUN_WITH_DISPLAY()                                                                                 \
  do {                                                                                                     \
    if (!::drape::testing::hasDisplay()) {                                                                 \
      if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0)                                         \
        GTEST_SKIP() << "no $DISPLAY and no xvfb-run (package xvfb) to make one";                          \
      EXPECT_EQ(::drape::testing::rerunUnderXvfb(), 0) << "the test failed under xvfb-run (output above)"; \
      return;                                                                                              \
    }                                                                                                      \
  } while (false)
