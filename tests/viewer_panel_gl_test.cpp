// The Dear ImGui panel drives the running simulation: real widgets, clicked and dragged through the
// pointer ImGui reads (ImGuiPanel::overridePointer), on a hidden window (under xvfb-run when there is no
// display). Each test checks the change reached the solver while it runs, not just the panel's fields.
#include "app/imgui_panel.hpp"
#include "core/colouring.hpp"
#include "core/metrics.hpp"
#include "core/scene.hpp"
#include "display_support.hpp"
#include "gpu/gpu_solver.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace drape {
namespace {

namespace fs = std::filesystem;

Scene pinned2() {
  return loadScene(fs::path(drape::test::sourceDir()) / "scenes" / "pinned2.json");
}

double centroidY(Solver& solver) {
  const std::vector<glm::dvec3> x = solver.readPositions();
  double sum = 0.0;
  for (const glm::dvec3& p : x)
    sum += p.y;
  return sum / double(x.size());
}

// The viewer on the GPU solver with the panel, in a window large enough to show all of the panel.
struct PanelSession {
  gl::WindowContext window;
  std::unique_ptr<Viewer> viewer;
  std::unique_ptr<ImGuiPanel> panel;
  const glm::vec2 away{900.0f, 700.0f};  // over the cloth view, not the panel

  explicit PanelSession(const Scene& scene) {
    window = gl::WindowContext::create(1000, 900, "panel test", false);
    viewer = std::make_unique<Viewer>(window, std::make_unique<GpuSolver>(scene), ViewerOptions{});
    panel = std::make_unique<ImGuiPanel>(window.window());
    // ImGui lays out an auto-sized window during its first frames before it shows it.
    for (int i = 0; i < 3; ++i)
      frame(away, false);
  }
  ~PanelSession() {
    panel.reset();
    viewer.reset();
  }

  void frame(glm::vec2 pointer, bool down) {
    panel->overridePointer(ImGuiPanel::Pointer{pointer, down});
    ASSERT_TRUE(viewer->frame(panel.get()));
  }
  ImGuiPanel::Rect control(const std::string& label) const {
    const std::optional<ImGuiPanel::Rect> r = panel->controlRect(label);
    EXPECT_TRUE(r.has_value()) << "no control labelled '" << label << "' in the panel";
    return r.value_or(ImGuiPanel::Rect{});
  }
  // Move there, press, release: one frame each, as a hand would.
  void click(glm::vec2 at) {
    frame(at, false);
    frame(at, true);
    frame(at, false);
    frame(away, false);
  }
  void drag(glm::vec2 from, glm::vec2 to, int moves) {
    frame(from, false);
    frame(from, true);
    for (int i = 1; i <= moves; ++i)
      frame(from + (to - from) * (float(i) / float(moves)), true);
    frame(to, false);
    frame(away, false);
  }
  // A slider's ends: just inside its frame, where ImGui clamps to min or max.
  static glm::vec2 sliderStart(const ImGuiPanel::Rect& r) { return {r.min.x + 2.0f, r.centre().y}; }
  static glm::vec2 sliderEnd(const ImGuiPanel::Rect& r) { return {r.min.x + r.frame_width - 2.0f, r.centre().y}; }
};

TEST(ViewerPanel, ShowsEveryParameterControl) {
  RUN_WITH_DISPLAY();
  PanelSession s(pinned2());
  for (const char* label : {"structural", "shearing", "bending", "ks (N/m)", "density (g/cm^2)", "damping (%)",
                            "frames/s", "steps/frame", "gravity (m/s^2)", "self-collision", "wind", "stretch passes"}) {
    const ImGuiPanel::Rect r = s.control(label);
    EXPECT_GT(r.max.x - r.min.x, 10.0f) << label;
    EXPECT_LT(r.max.y, 900.0f) << label << " is below the bottom of the window";
  }
  EXPECT_FALSE(s.panel->capturesMouse());  // the pointer is over the cloth view
  s.frame(s.control("ks (N/m)").centre(), false);
  EXPECT_TRUE(s.panel->capturesMouse());  // over the panel: the camera must not orbit
}

TEST(ViewerPanel, DraggingGravityUpwardsLiftsTheRunningCloth) {
  RUN_WITH_DISPLAY();
  PanelSession s(pinned2());
  Viewer& v = *s.viewer;
  const ImGuiPanel::Rect gravity = s.control("gravity (m/s^2)");
  // DragFloat3 splits its width into x, y and z fields; the y field is in the middle.
  const glm::vec2 y_field{gravity.min.x + 0.5f * gravity.frame_width, gravity.centre().y};
  const double before_y = centroidY(v.solver());
  s.drag(y_field, y_field + glm::vec2(300.0f, 0.0f), 10);  // 0.1 m/s^2 per pixel
  EXPECT_GT(v.sim.gravity.y, 10.0);
  EXPECT_EQ(v.solver().scene().sim.gravity.y, v.sim.gravity.y);  // handed to the solver, not only the panel
  EXPECT_EQ(v.sim.gravity.x, 0.0);
  const double lifted_from = centroidY(v.solver());
  EXPECT_LT(lifted_from, before_y);  // it fell while the drag began
  for (int i = 0; i < 30; ++i)
    s.frame(s.away, false);
  EXPECT_GT(centroidY(v.solver()), lifted_from + 0.05) << "the cloth should swing up under upward gravity";
  EXPECT_TRUE(v.blowUp().empty());
}

TEST(ViewerPanel, StepsPerFrameAndSelfCollisionChangeWhatTheSolverDispatches) {
  RUN_WITH_DISPLAY();
  PanelSession s(pinned2());
  Viewer& v = *s.viewer;
  const std::vector<std::string> passes = v.solver().passes();
  ASSERT_EQ(passes.size(), 13u);  // forces+integrate, then the stretch limit's 12 colours

  s.click(s.control("self-collision").centre());
  EXPECT_TRUE(v.sim.self_collision);
  const std::vector<std::string> with = v.solver().passes();
  EXPECT_GT(with.size(), passes.size());
  EXPECT_TRUE(std::any_of(with.begin(), with.end(), [](const std::string& p) {
    return p.find("self_collide") != std::string::npos;
  })) << "self-collision is on but no self_collide pass is dispatched";

  s.click(PanelSession::sliderEnd(s.control("steps/frame")));
  EXPECT_EQ(v.sim.steps_per_frame, 200);
  const long long substeps = v.solver().substeps();
  s.frame(s.away, false);
  EXPECT_EQ(v.solver().substeps() - substeps, 200);
  EXPECT_EQ(v.solver().dispatchesPerFrame(), int(with.size()) * 200 + int(v.solver().framePasses().size()));

  s.click(PanelSession::sliderStart(s.control("damping (%)")));
  EXPECT_EQ(v.cloth.damping, 0.0);
  EXPECT_EQ(v.solver().scene().cloth.damping, 0.0);
}

TEST(ViewerPanel, TheIntegratorButtonsAndTethersCheckboxSwitchTheRunningSolver) {
  RUN_WITH_DISPLAY();
  PanelSession s(pinned2());
  Viewer& v = *s.viewer;
  EXPECT_FALSE(s.panel->controlRect("iterations").has_value());  // Verlet has no sweeps to set
  s.click(s.control("xpbd").centre());
  EXPECT_EQ(v.sim.integrator, Integrator::Xpbd);
  EXPECT_EQ(v.solver().scene().sim.integrator, Integrator::Xpbd);  // handed to the solver, not only the panel
  const std::vector<std::string> passes = v.solver().passes();
  ASSERT_FALSE(passes.empty());
  EXPECT_EQ(passes.front(), "forces+predict");
  EXPECT_EQ(std::count(passes.begin(), passes.end(), "xpbd_colour"), 12);  // one sweep over the 12 colours
  s.frame(s.away, false);  // the iterations slider appears from the next frame
  s.click(PanelSession::sliderEnd(s.control("iterations")));
  EXPECT_EQ(v.solver().scene().sim.iterations, 10);
  const std::vector<std::string> swept = v.solver().passes();
  EXPECT_EQ(std::count(swept.begin(), swept.end(), "xpbd_colour"), 120);
  // Tethers to the pins, live: built on the first click, a pass before the stretch limit.
  s.click(s.control("tethers").centre());
  EXPECT_TRUE(v.solver().scene().sim.tethers);
  const std::vector<std::string> tethered = v.solver().passes();
  EXPECT_EQ(std::count(tethered.begin(), tethered.end(), "tether"), 1);
  for (int i = 0; i < 20; ++i)
    s.frame(s.away, false);
  EXPECT_TRUE(v.blowUp().empty()) << v.blowUp();
  // VBD on the same state, its 10 sweeps kept: one dispatch per point colour and sweep.
  s.click(s.control("vbd").centre());
  EXPECT_EQ(v.solver().scene().sim.integrator, Integrator::Vbd);
  const std::vector<std::string> vbd = v.solver().passes();
  EXPECT_EQ(std::count(vbd.begin(), vbd.end(), "xpbd_colour"), 0);
  EXPECT_EQ(std::count(vbd.begin(), vbd.end(), "vbd_colour"), 10 * colourPoints(v.solver().topology()).colourCount());
  for (int i = 0; i < 20; ++i)
    s.frame(s.away, false);
  EXPECT_TRUE(v.blowUp().empty()) << v.blowUp();
  s.click(s.control("verlet").centre());
  EXPECT_EQ(v.solver().scene().sim.integrator, Integrator::Verlet);
  s.frame(s.away, false);
  EXPECT_FALSE(s.panel->controlRect("iterations").has_value()) << "Verlet has no sweeps to set";
}

TEST(ViewerPanel, CrossingTheStabilityBoundIsReportedAndOneClickFixesIt) {
  RUN_WITH_DISPLAY();
  Scene scene = pinned2();
  scene.sim.steps_per_frame = 10;  // inside the bound at 5000 N/m, outside it at 1e5 N/m
  PanelSession s(scene);
  Viewer& v = *s.viewer;
  ASSERT_TRUE(v.stability().ok) << v.stability().message;
  EXPECT_FALSE(s.panel->controlRect("auto substeps").has_value());

  s.click(s.control("pause").centre());  // so that it cannot blow up while we look
  ASSERT_TRUE(v.paused());
  s.click(PanelSession::sliderEnd(s.control("ks (N/m)")));
  EXPECT_EQ(v.cloth.ks, 1e5);
  EXPECT_FALSE(v.stability().ok);
  EXPECT_NE(v.status().find("bound crossed"), std::string::npos) << v.status();

  const int need = autoSubsteps([&] {
    Scene edited = scene;
    edited.cloth = v.cloth;
    edited.sim = v.sim;
    return edited;
  }());
  ASSERT_GT(need, 10);
  s.click(s.control("auto substeps").centre());
  EXPECT_EQ(v.sim.steps_per_frame, need);
  EXPECT_EQ(v.solver().scene().sim.steps_per_frame, need);
  EXPECT_TRUE(v.stability().ok) << v.stability().message;
  EXPECT_EQ(v.status(), "back inside the stability bound");

  s.click(s.control("pause").centre());
  ASSERT_FALSE(v.paused());
  const long long frames = v.framesSimulated();
  for (int i = 0; i < 20; ++i)
    s.frame(s.away, false);
  EXPECT_EQ(v.framesSimulated(), frames + 20);
  EXPECT_EQ(v.blowUp(), "");
  const std::vector<glm::dvec3> x = v.solver().readPositions();
  EXPECT_TRUE(allFinite(x));
}

TEST(ViewerPanel, ABlowUpPausesTheViewerUntilReset) {
  RUN_WITH_DISPLAY();
  Scene scene = pinned2();
  scene.sim.steps_per_frame = 10;
  // Without a stretch limit: the Gauss-Seidel pass holds even this stiff cloth together, jittering.
  scene.sim.stretch_passes = 0;
  PanelSession s(scene);
  Viewer& v = *s.viewer;
  const long long drawn_before = v.clothDraws();
  s.frame(s.away, false);
  ASSERT_GT(v.clothDraws(), drawn_before) << "a running cloth is drawn every frame";
  s.click(PanelSession::sliderEnd(s.control("ks (N/m)")));  // 1e5 N/m at 10 substeps: far outside the bound
  for (int i = 0; i < 60 && v.blowUp().empty(); ++i)
    s.frame(s.away, false);
  ASSERT_NE(v.blowUp(), "") << "1e5 N/m at 10 substeps per frame should blow up within 60 frames";
  EXPECT_TRUE(v.paused());
  // Hidden: the frames after the blow-up draw the scene and the panel, but not the cloth.
  const long long drawn_at_blow_up = v.clothDraws();
  for (int i = 0; i < 3; ++i)
    s.frame(s.away, false);
  EXPECT_EQ(v.clothDraws(), drawn_at_blow_up) << "a blown-up cloth must not be drawn";
  // The check is a frame late on the GPU (Solver::recentHealth): the frame named is the last or the one before.
  const std::string named = "blow-up at frame ";
  EXPECT_TRUE(v.status().find(named + std::to_string(v.framesSimulated())) != std::string::npos ||
              v.status().find(named + std::to_string(v.framesSimulated() - 1)) != std::string::npos)
      << v.status();
  const long long frames = v.framesSimulated();
  s.click(s.control("pause").centre());  // resuming does not step a blown-up cloth
  s.click(s.control("step").centre());
  EXPECT_EQ(v.framesSimulated(), frames);

  s.click(PanelSession::sliderStart(s.control("ks (N/m)")));
  s.click(s.control("reset").centre());
  EXPECT_EQ(v.blowUp(), "");
  EXPECT_EQ(v.status(), "");
  ASSERT_FALSE(v.paused());  // resumed above, and the reset lets it run again
  const long long restarted = v.framesSimulated();
  const long long drawn_after_reset = v.clothDraws();
  for (int i = 0; i < 10; ++i)
    s.frame(s.away, false);
  EXPECT_EQ(v.framesSimulated(), restarted + 10);
  EXPECT_EQ(v.blowUp(), "");
  EXPECT_GT(v.clothDraws(), drawn_after_reset) << "shown again after the reset";
}

}  // namespace
}  // namespace drape
