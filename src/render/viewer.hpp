// The interactive viewer: a GLFW window that steps the solver and draws it every frame, with the
// CS184 keys and mouse (orbit, pan, zoom), live parameter changes, shader reloading, screenshots and
// dragging a cloth point. The control panel is supplied by the caller (ViewerPanel) so that this layer
// does not depend on the GUI library.
#pragma once

#include "core/solver.hpp"
#include "core/stability.hpp"
#include "gl/context.hpp"
#include "gl/objects.hpp"
#include "render/camera.hpp"
#include "render/cloth_feed.hpp"
#include "render/renderer.hpp"

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace drape {

class GpuSolver;
class Viewer;

// Keys, as in CS184 where it has them.
struct ViewerKeys {
  static constexpr int kPause = 'P';
  static constexpr int kReset = 'R';
  static constexpr int kStep = 'N';
  static constexpr int kScreenshot = 'S';
  static constexpr int kResetCamera = ' ';
  static constexpr int kTogglePanel = 'H';
  static constexpr int kReloadShaders = 294;  // GLFW_KEY_F5
  static constexpr int kQuit = 256;           // GLFW_KEY_ESCAPE
};

// The keys and the mouse, as `view --help`, the panel and the README list them: "Keys:" then one line a
// key, "Mouse:" then one line a gesture.
std::string viewerControlsText();

// The on-screen panel. Dear ImGui lives in the app layer; it reaches the viewer through this.
class ViewerPanel {
 public:
  virtual ~ViewerPanel() = default;
  virtual void draw(Viewer& viewer) = 0;  // build and render the panel over the frame just drawn
  virtual bool capturesMouse() const = 0;
  virtual bool capturesKeyboard() const = 0;
};

struct ViewerOptions {
  RendererOptions renderer;
  // Where the cloth goes (render/framing.hpp): what the camera frames (Space) and the floor, the light and
  // the shadow map follow. Empty: the scene as it starts.
  std::optional<SceneExtent> extent;
  Shading shading = Shading::Phong;
  int frames = 0;                              // > 0: simulate this many frames, save `screenshot`, close
  std::filesystem::path screenshot;            // with `frames`
  std::filesystem::path screenshot_dir = ".";  // where S writes
};

// Rolling measurements over the last second, for the panel.
struct ViewerStats {
  double fps = 0.0;
  double frame_ms = 0.0;     // wall clock per displayed frame
  double simulate_ms = 0.0;  // per frame, stepping the solver
  double draw_ms = 0.0;      // per frame, normals + drawing the scene
  struct Pass {
    std::string name;
    double ms = 0.0;               // per frame
    double calls_per_frame = 0.0;  // dispatches (GPU) or invocations (CPU)
  };
  std::vector<Pass> passes;  // from the solver's timings
  bool pass_ms = true;       // Pass::ms measured (the GPU solver times passes only where timer queries work)
};

class Viewer {
 public:
  // Takes the solver (built on `window`'s context). Throws what Renderer throws.
  Viewer(gl::WindowContext& window, std::unique_ptr<Solver> solver, const ViewerOptions& options);
  ~Viewer();
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  // Until Esc or the window closes, or `frames` frames in the --frames mode. `panel` may be null.
  void run(ViewerPanel* panel);
  // One iteration of run(): events, simulation, drawing, panel, swap. False once the viewer should close.
  bool frame(ViewerPanel* panel);

  // Input, as GLFW reports it (window coordinates, origin top-left). Public so tests can drive them.
  void onKey(int key, int action, int mods);
  void onMouseButton(int button, int action, int mods, glm::vec2 cursor);
  void onCursor(double x, double y);
  void onScroll(double dy);

  // What the panel edits. Parameters take effect on applyParams(), which also checks them against the
  // explicit-integration bound (core/stability.hpp) and says so in status() when they cross it; render
  // settings take effect immediately.
  ClothSpec cloth;
  SimParams sim;
  RenderSettings settings;
  void applyParams();
  const StabilityCheck& stability() const { return stability_; }

  bool paused() const { return paused_; }
  // The panel is drawn (and takes the mouse and keys over it) only while shown; H toggles it.
  bool panelShown() const { return panel_shown_; }
  void setPanelShown(bool shown) { panel_shown_ = shown; }
  void setPaused(bool paused) { paused_ = paused; }
  void stepOnce() { step_once_ = true; }
  void resetCloth();
  void resetCamera();
  void reloadShaders();
  void requestScreenshot(std::filesystem::path file = {});  // default: a new numbered file
  void quit() { quit_ = true; }

  Solver& solver() { return *solver_; }
  const Scene& scene() const { return scene_; }
  const Camera& camera() const { return camera_; }
  const gl::ContextInfo& contextInfo() const { return window_->info(); }
  long long framesSimulated() const { return frames_simulated_; }
  const ViewerStats& stats() const { return stats_; }
  const std::string& shaderErrors() const { return shader_errors_; }  // of the last failed reload
  const std::string& status() const { return status_; }               // last message (screenshot saved, ...)
  // Why the simulation stopped: non-empty once a frame ended with a non-finite or runaway point (the
  // viewer then pauses, stops drawing the cloth and refuses to step until R resets it).
  const std::string& blowUp() const { return blow_up_; }
  long long clothDraws() const { return renderer_.clothDraws(); }  // how often the cloth was drawn
  bool canDrag() const { return gpu_ != nullptr; }
  int draggedPoint() const { return drag_point_; }

 private:
  enum class MouseMode { None, Orbit, Pan, Drag };

  void simulateFrame();
  void drawScene();
  void saveScreenshot(const std::filesystem::path& file);
  void startDrag(glm::vec2 cursor);
  void updateDrag(glm::vec2 cursor);
  void endDrag();
  glm::vec2 toFramebuffer(glm::vec2 cursor) const;
  void updateStats();
  bool panelTakesMouse() const;
  bool panelTakesKeys() const;

  gl::WindowContext* window_;
  ViewerOptions options_;
  std::unique_ptr<Solver> solver_;
  GpuSolver* gpu_ = nullptr;  // solver_ when it runs on the GPU (dragging needs it)
  Scene scene_;
  ClothFeed feed_;
  Renderer renderer_;
  Camera camera_;
  ClothBuffers cloth_buffers_;

  bool paused_ = false;
  bool panel_shown_ = true;
  bool step_once_ = false;
  bool quit_ = false;
  std::optional<std::filesystem::path> screenshot_request_;
  int screenshot_counter_ = 0;
  std::string shader_errors_;
  std::string status_;
  std::string blow_up_;
  StabilityCheck stability_;

  MouseMode mouse_mode_ = MouseMode::None;
  glm::vec2 last_cursor_{0.0f};
  int drag_point_ = -1;
  glm::vec3 drag_plane_point_{0.0f};
  glm::vec3 drag_plane_normal_{0.0f};
  ViewerPanel* panel_ = nullptr;

  long long frames_simulated_ = 0;
  ViewerStats stats_;
  struct Accumulator {
    std::chrono::steady_clock::time_point since = std::chrono::steady_clock::now();
    int frames = 0;
    double simulate_ms = 0.0, draw_ms = 0.0;
  } accumulator_;
};

}  // namespace drape
