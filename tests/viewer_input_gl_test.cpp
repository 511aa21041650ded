// The viewer's keys and mouse, driven in-process on a hidden GLFW window (under xvfb-run when there is
// no display, see display_support.hpp).
#include "core/scene.hpp"
#include "display_support.hpp"
#include "gl/shader_source.hpp"
#include "gpu/gpu_solver.hpp"
#include "render/viewer.hpp"
#include "test_paths.hpp"

#include <GLFW/glfw3.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>

namespace drape {
namespace {

namespace fs = std::filesystem;

class FakePanel final : public ViewerPanel {
 public:
  bool mouse = false, keyboard = false;
  int draws = 0;
  void draw(Viewer&) override { ++draws; }
  bool capturesMouse() const override { return mouse; }
  bool capturesKeyboard() const override { return keyboard; }
};

Scene sphereScene() {
  return loadScene(fs::path(drape::test::sourceDir()) / "scenes" / "sphere.json");
}

// A hidden 320x240 window with the viewer on the GPU solver.
struct Session {
  gl::WindowContext window;
  GpuSolver* gpu = nullptr;
  std::unique_ptr<Viewer> viewer;
  fs::path dir = fs::temp_directory_path() / ("drape_viewer_" + std::to_string(::getpid()));

  Session() {
    window = gl::WindowContext::create(320, 240, "viewer test", false);
    auto solver = std::make_unique<GpuSolver>(sphereScene());
    gpu = solver.get();
    fs::create_directories(dir);
    ViewerOptions options;
    options.screenshot_dir = dir;
    viewer = std::make_unique<Viewer>(window, std::move(solver), options);
  }
  ~Session() {
    viewer.reset();
    fs::remove_all(dir);
  }
  void press(int key) { viewer->onKey(key, GLFW_PRESS, 0); }
};

TEST(ViewerInput, KeysControlTheSimulation) {
  RUN_WITH_DISPLAY();
  Session s;
  Viewer& v = *s.viewer;
  const int steps = v.scene().sim.steps_per_frame;
  ASSERT_TRUE(v.frame(nullptr));
  EXPECT_EQ(v.framesSimulated(), 1);

  s.press(ViewerKeys::kPause);
  EXPECT_TRUE(v.paused());
  ASSERT_TRUE(v.frame(nullptr));
  EXPECT_EQ(v.framesSimulated(), 1);  // paused: drawn, not stepped
  s.press(ViewerKeys::kStep);
  ASSERT_TRUE(v.frame(nullptr));
  ASSERT_TRUE(v.frame(nullptr));
  EXPECT_EQ(v.framesSimulated(), 2);  // N: exactly one frame
  EXPECT_EQ(v.solver().substeps(), 2LL * steps);

  s.press(ViewerKeys::kReset);
  EXPECT_EQ(v.framesSimulated(), 0);
  EXPECT_EQ(v.solver().substeps(), 0);
  s.press(ViewerKeys::kPause);
  EXPECT_FALSE(v.paused());

  // While the panel has the keyboard (typing into a field), keys are its own.
  FakePanel panel;
  panel.keyboard = true;
  ASSERT_TRUE(v.frame(&panel));
  s.press(ViewerKeys::kPause);
  EXPECT_FALSE(v.paused());
  EXPECT_EQ(panel.draws, 1);
  panel.keyboard = false;

  s.press(ViewerKeys::kScreenshot);
  ASSERT_TRUE(v.frame(&panel));
  const fs::path shot = s.dir / "drape_screenshot_001.png";
  EXPECT_TRUE(fs::exists(shot)) << v.status();

  // A broken shader: the reload reports it with file and line and the old programs keep drawing.
  const fs::path glsl = s.dir / "glsl";
  fs::copy(gl::glslRoot(), glsl, fs::copy_options::recursive);
  std::ofstream(glsl / "render" / "toon.frag", std::ios::app) << "\nint broken = ;\n";
  ::setenv("DRAPE_GLSL_DIR", glsl.string().c_str(), 1);
  s.press(ViewerKeys::kReloadShaders);
  ::unsetenv("DRAPE_GLSL_DIR");
  EXPECT_NE(v.shaderErrors().find("toon.frag:"), std::string::npos) << v.shaderErrors();
  v.settings.shading = Shading::Toon;
  EXPECT_TRUE(v.frame(&panel));
  s.press(ViewerKeys::kReloadShaders);
  EXPECT_EQ(v.shaderErrors(), "");

  s.press(ViewerKeys::kQuit);
  EXPECT_FALSE(v.frame(&panel));
}

// H hides the panel: it is no longer drawn, and its last answer no longer keeps the mouse and the keys from
// the view; H again brings it back.
TEST(ViewerInput, HHidesAndShowsThePanel) {
  RUN_WITH_DISPLAY();
  Session s;
  Viewer& v = *s.viewer;
  FakePanel panel;
  panel.mouse = true;
  panel.keyboard = false;
  ASSERT_TRUE(v.frame(&panel));
  EXPECT_EQ(panel.draws, 1);
  const float distance = v.camera().distance();
  v.onScroll(1.0);
  EXPECT_EQ(v.camera().distance(), distance) << "the pointer is over the panel";

  s.press(ViewerKeys::kTogglePanel);
  EXPECT_FALSE(v.panelShown());
  ASSERT_TRUE(v.frame(&panel));
  EXPECT_EQ(panel.draws, 1) << "a hidden panel is not drawn";
  v.onScroll(1.0);
  EXPECT_LT(v.camera().distance(), distance) << "a hidden panel does not take the mouse";
  panel.keyboard = true;
  s.press(ViewerKeys::kPause);
  EXPECT_TRUE(v.paused()) << "nor the keys";

  s.press(ViewerKeys::kTogglePanel);
  EXPECT_TRUE(v.panelShown());
  ASSERT_TRUE(v.frame(&panel));
  EXPECT_EQ(panel.draws, 2);
}

TEST(ViewerInput, MouseOrbitsPansAndZooms) {
  RUN_WITH_DISPLAY();
  Session s;
  Viewer& v = *s.viewer;
  ASSERT_TRUE(v.frame(nullptr));
  const glm::vec3 home = v.camera().position(), target = v.camera().target();
  const float distance = v.camera().distance();

  v.onMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, 0, {100.0f, 100.0f});
  v.onCursor(160.0, 130.0);
  v.onMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, 0, {160.0f, 130.0f});
  EXPECT_GT(glm::distance(v.camera().position(), home), 0.1f);
  EXPECT_NEAR(glm::distance(v.camera().position(), v.camera().target()), distance, 1e-4f);
  EXPECT_EQ(v.camera().target(), target);  // orbit turns about the target
  v.onCursor(10.0, 10.0);                  // moving without a button does nothing
  s.press(ViewerKeys::kResetCamera);
  EXPECT_LT(glm::distance(v.camera().position(), home), 1e-5f);

  for (int mods : {0, GLFW_MOD_CONTROL}) {
    const int button = mods ? GLFW_MOUSE_BUTTON_LEFT : GLFW_MOUSE_BUTTON_RIGHT;
    v.onMouseButton(button, GLFW_PRESS, mods, {100.0f, 100.0f});
    v.onCursor(140.0, 100.0);
    v.onMouseButton(button, GLFW_RELEASE, mods, {140.0f, 100.0f});
    EXPECT_GT(glm::distance(v.camera().target(), target), 0.01f) << (mods ? "ctrl+left" : "right");
    EXPECT_NEAR(v.camera().distance(), distance, 1e-5f);
    s.press(ViewerKeys::kResetCamera);
  }

  v.onScroll(2.0);
  EXPECT_LT(v.camera().distance(), distance);
  FakePanel panel;
  panel.mouse = true;
  ASSERT_TRUE(v.frame(&panel));
  const float zoomed = v.camera().distance();
  v.onScroll(2.0);  // over the panel: the panel scrolls, not the camera
  EXPECT_EQ(v.camera().distance(), zoomed);
}

TEST(ViewerInput, ShiftDragHoldsAClothPointOnTheGpu) {
  RUN_WITH_DISPLAY();
  Session s;
  Viewer& v = *s.viewer;
  ASSERT_TRUE(v.canDrag());
  s.press(ViewerKeys::kPause);
  ASSERT_TRUE(v.frame(nullptr));
  const Topology& topo = v.solver().topology();
  const int centre = 25 * topo.W + 25;
  const glm::vec3 start = glm::vec3(v.solver().readPositions()[std::size_t(centre)]);
  const glm::ivec2 size = s.window.framebufferSize();
  const glm::vec4 clip = v.camera().viewProjection(float(size.x) / float(size.y)) * glm::vec4(start, 1.0f);
  const glm::vec2 pixel{(clip.x / clip.w * 0.5f + 0.5f) * float(size.x),
                        (0.5f - clip.y / clip.w * 0.5f) * float(size.y)};

  v.onMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, GLFW_MOD_SHIFT, pixel);
  const int held = v.draggedPoint();
  ASSERT_GE(held, 0) << v.status();
  EXPECT_LE(std::abs(held % topo.W - 25), 1);
  EXPECT_LE(std::abs(held / topo.W - 25), 1);
  v.onCursor(pixel.x, pixel.y - 40.0f);  // drag upwards on the screen
  s.press(ViewerKeys::kStep);
  ASSERT_TRUE(v.frame(nullptr));
  const glm::vec3 moved = glm::vec3(v.solver().readPositions()[std::size_t(held)]);
  EXPECT_GT(moved.y, start.y + 0.05f) << "the held point follows the cursor up";
  v.onMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, GLFW_MOD_SHIFT, {pixel.x, pixel.y - 40.0f});
  EXPECT_EQ(v.draggedPoint(), -1);
}

}  // namespace
}  // namespace drape
