#include "render/viewer.hpp"

#include "gl/debug.hpp"
#include "gpu/gpu_solver.hpp"
#include "render/image.hpp"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace drape {

static_assert(ViewerKeys::kPause == GLFW_KEY_P && ViewerKeys::kReset == GLFW_KEY_R && ViewerKeys::kStep == GLFW_KEY_N &&
              ViewerKeys::kScreenshot == GLFW_KEY_S && ViewerKeys::kResetCamera == GLFW_KEY_SPACE &&
              ViewerKeys::kReloadShaders == GLFW_KEY_F5 && ViewerKeys::kQuit == GLFW_KEY_ESCAPE &&
              ViewerKeys::kTogglePanel == GLFW_KEY_H);

namespace {

constexpr float kOrbitPerPixel = 0.008f;  // rad
constexpr float kZoomPerNotch = 0.9f;

Viewer& viewerOf(GLFWwindow* window) {
  return *static_cast<Viewer*>(glfwGetWindowUserPointer(window));
}

// GLFW calls these from glfwPollEvents; Dear ImGui's backend, installed after them, chains to them.
void keyCallback(GLFWwindow* w, int key, int /*scancode*/, int action, int mods) {
  viewerOf(w).onKey(key, action, mods);
}
void mouseButtonCallback(GLFWwindow* w, int button, int action, int mods) {
  double x = 0.0, y = 0.0;
  glfwGetCursorPos(w, &x, &y);
  viewerOf(w).onMouseButton(button, action, mods, {float(x), float(y)});
}
void cursorCallback(GLFWwindow* w, double x, double y) {
  viewerOf(w).onCursor(x, y);
}
void scrollCallback(GLFWwindow* w, double /*dx*/, double dy) {
  viewerOf(w).onScroll(dy);
}

}  // namespace

std::string viewerControlsText() {
  struct Control {
    const char* input;
    const char* action;
  };
  static const Control keys[] = {
      {"P", "pause / resume"},        {"N", "one frame, while paused"},
      {"R", "reset the cloth"},       {"Space", "reset the camera"},
      {"H", "hide / show the panel"}, {"S", "screenshot (drape_screenshot_NNN.png, in the current folder)"},
      {"F5", "reload the shaders"},   {"Esc", "quit"}};
  static const Control mouse[] = {{"left-drag", "orbit"},
                                  {"right-drag, Ctrl+left-drag", "pan"},
                                  {"scroll", "zoom"},
                                  {"Shift+left-drag", "pull the cloth (GPU solver)"}};
  std::string text = "Keys:\n";
  for (const Control& c : keys)
    text += "  " + std::string(c.input) + std::string(28 - std::string(c.input).size(), ' ') + c.action + "\n";
  text += "Mouse:\n";
  for (const Control& c : mouse)
    text += "  " + std::string(c.input) + std::string(28 - std::string(c.input).size(), ' ') + c.action + "\n";
  return text;
}

Viewer::Viewer(gl::WindowContext& window, std::unique_ptr<Solver> solver, const ViewerOptions& options)
    : cloth(solver->scene().cloth),
      sim(solver->scene().sim),
      window_(&window),
      options_(options),
      solver_(std::move(solver)),
      gpu_(dynamic_cast<GpuSolver*>(solver_.get())),
      scene_(solver_->scene()),
      feed_(*solver_),
      renderer_(scene_, solver_->topology(),
                options.extent ? *options.extent : SceneExtent(scene_, solver_->topology()), options.renderer) {
  settings.shading = options.shading;
  settings.light = renderer_.defaultLight();
  settings.springs = enabledSprings(cloth);
  stability_ = checkStability(scene_);
  if (!stability_.ok) status_ = stability_.message;
  resetCamera();
  GLFWwindow* w = window.window();
  glfwSetWindowUserPointer(w, this);
  glfwSetKeyCallback(w, keyCallback);
  glfwSetMouseButtonCallback(w, mouseButtonCallback);
  glfwSetCursorPosCallback(w, cursorCallback);
  glfwSetScrollCallback(w, scrollCallback);
  solver_->resetTimings();
}

Viewer::~Viewer() {
  if (GLFWwindow* w = window_->window()) {
    glfwSetKeyCallback(w, nullptr);
    glfwSetMouseButtonCallback(w, nullptr);
    glfwSetCursorPosCallback(w, nullptr);
    glfwSetScrollCallback(w, nullptr);
    glfwSetWindowUserPointer(w, nullptr);
  }
}

void Viewer::run(ViewerPanel* panel) {
  while (frame(panel)) {
  }
}

bool Viewer::frame(ViewerPanel* panel) {
  panel_ = panel;
  glfwPollEvents();
  if (quit_ || glfwWindowShouldClose(window_->window())) return false;
  if ((!paused_ || step_once_) && blow_up_.empty()) {
    simulateFrame();
    step_once_ = false;
  }
  drawScene();
  const bool done = options_.frames > 0 && frames_simulated_ >= options_.frames;
  if (done && !options_.screenshot.empty()) saveScreenshot(options_.screenshot);
  if (screenshot_request_) {
    saveScreenshot(*screenshot_request_);
    screenshot_request_.reset();
  }
  if (panel && panel_shown_) panel->draw(*this);
  glfwSwapBuffers(window_->window());
  updateStats();
  return !done;
}

void Viewer::simulateFrame() {
  const auto start = std::chrono::steady_clock::now();
  solver_->stepFrame();
  ++frames_simulated_;
  // Every frame, without a wait: on the GPU the answer is a frame late (Solver::recentHealth), and the
  // cloth's vertex shaders hide a cloth whose flags are raised, so no frame of garbage is drawn meanwhile.
  if (const Health h = solver_->recentHealth(); !h.ok()) {
    const long long late = (solver_->substeps() - h.substeps) / std::max(1, sim.steps_per_frame);
    blow_up_ = "blow-up at frame " + std::to_string(frames_simulated_ - late) + ": " + h.describe();
    paused_ = true;
    status_ = blow_up_ + ". Paused; R resets the cloth (lower ks or raise steps/frame first).";
    std::fprintf(stderr, "drape view: %s\n", status_.c_str());
  }
  accumulator_.simulate_ms +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void Viewer::drawScene() {
  const glm::ivec2 size = window_->framebufferSize();
  if (size.x <= 0 || size.y <= 0) return;  // minimised
  const auto start = std::chrono::steady_clock::now();
  cloth_buffers_ = feed_.prepare();
  gl::Framebuffer::bindDefault();
  RenderSettings shown = settings;
  shown.show_cloth = settings.show_cloth && blow_up_.empty();
  renderer_.draw(cloth_buffers_, camera_, size, shown);
  accumulator_.draw_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void Viewer::updateStats() {
  ++accumulator_.frames;
  const auto now = std::chrono::steady_clock::now();
  const double seconds = std::chrono::duration<double>(now - accumulator_.since).count();
  if (seconds < 1.0) return;
  const double frames = accumulator_.frames;
  stats_.fps = frames / seconds;
  stats_.frame_ms = 1000.0 * seconds / frames;
  stats_.simulate_ms = accumulator_.simulate_ms / frames;
  stats_.draw_ms = accumulator_.draw_ms / frames;
  stats_.passes.clear();
  stats_.pass_ms = gpu_ == nullptr || gpu_->timesPasses();
  for (const PassTiming& p : solver_->timings())
    stats_.passes.push_back({p.name, p.ms / frames, double(p.calls) / frames});
  solver_->resetTimings();
  accumulator_ = Accumulator{};
}

void Viewer::applyParams() {
  solver_->setParams(cloth, sim);
  settings.springs = enabledSprings(cloth);
  const bool was_ok = stability_.ok;
  stability_ = checkStability(solver_->scene());  // what the solver now runs
  if (!stability_.ok) {
    status_ = stability_.message;
  } else if (!was_ok) {
    status_ = "back inside the stability bound";
  }
}

void Viewer::resetCloth() {
  endDrag();
  solver_->reset();
  frames_simulated_ = 0;
  if (!blow_up_.empty()) {
    blow_up_.clear();
    status_.clear();
  }
}

void Viewer::resetCamera() {
  const glm::ivec2 size = window_->framebufferSize();
  camera_.frame(renderer_.framingSubject(), size.y > 0 ? float(size.x) / float(size.y) : 4.0f / 3.0f);
}

void Viewer::reloadShaders() {
  shader_errors_ = renderer_.reloadShaders();
  if (shader_errors_.empty()) {
    status_ = "shaders reloaded";
  } else {
    status_ = "shader reload failed; the previous programs stay in use";
    std::fprintf(stderr, "drape view: %s\n%s", status_.c_str(), shader_errors_.c_str());
  }
}

void Viewer::requestScreenshot(std::filesystem::path file) {
  if (file.empty()) {
    do {
      char name[64];
      std::snprintf(name, sizeof name, "drape_screenshot_%03d.png", ++screenshot_counter_);
      file = options_.screenshot_dir / name;
    } while (std::filesystem::exists(file));
  }
  screenshot_request_ = std::move(file);
}

void Viewer::saveScreenshot(const std::filesystem::path& file) {
  const glm::ivec2 size = window_->framebufferSize();
  Image image{size.x, size.y, 3, std::vector<std::uint8_t>(std::size_t(size.x) * size.y * 3)};
  // The explicit read-back of a screenshot: the back buffer, before the panel is drawn over it.
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, size.x, size.y, GL_RGB, GL_UNSIGNED_BYTE, image.pixels.data());
  flipRows(image);
  try {
    writePng(file, image);
    status_ = "saved " + file.string();
    std::fprintf(stderr, "drape view: %s\n", status_.c_str());
  } catch (const std::runtime_error& e) {  // ImageError, or OutputError from the file system
    status_ = e.what();
    std::fprintf(stderr, "drape view: %s\n", e.what());
    if (options_.frames > 0) throw;  // the --frames run exists to write this file
  }
}

void Viewer::onKey(int key, int action, int /*mods*/) {
  if (action != GLFW_PRESS) return;
  if (panelTakesKeys()) return;
  switch (key) {
    case ViewerKeys::kPause:
      paused_ = !paused_;
      break;
    case ViewerKeys::kReset:
      resetCloth();
      break;
    case ViewerKeys::kStep:
      if (paused_) step_once_ = true;
      break;
    case ViewerKeys::kResetCamera:
      resetCamera();
      break;
    case ViewerKeys::kTogglePanel:
      panel_shown_ = !panel_shown_;
      break;
    case ViewerKeys::kScreenshot:
      requestScreenshot();
      break;
    case ViewerKeys::kReloadShaders:
      reloadShaders();
      break;
    case ViewerKeys::kQuit:
      quit_ = true;
      break;
    default:
      break;
  }
}

void Viewer::onMouseButton(int button, int action, int mods, glm::vec2 cursor) {
  if (action == GLFW_RELEASE) {
    if (mouse_mode_ == MouseMode::Drag) endDrag();
    mouse_mode_ = MouseMode::None;
    return;
  }
  if (action != GLFW_PRESS || panelTakesMouse()) return;
  last_cursor_ = cursor;
  if (button == GLFW_MOUSE_BUTTON_RIGHT || (button == GLFW_MOUSE_BUTTON_LEFT && (mods & GLFW_MOD_CONTROL))) {
    mouse_mode_ = MouseMode::Pan;
  } else if (button == GLFW_MOUSE_BUTTON_LEFT && (mods & GLFW_MOD_SHIFT)) {
    startDrag(last_cursor_);
  } else if (button == GLFW_MOUSE_BUTTON_LEFT) {
    mouse_mode_ = MouseMode::Orbit;
  }
}

void Viewer::onCursor(double x, double y) {
  const glm::vec2 cursor{float(x), float(y)};
  const glm::vec2 delta = cursor - last_cursor_;
  last_cursor_ = cursor;
  switch (mouse_mode_) {
    case MouseMode::Orbit:
      camera_.orbit(-delta.x * kOrbitPerPixel, delta.y * kOrbitPerPixel);
      break;
    case MouseMode::Pan: {
      int width = 0, height = 0;
      glfwGetWindowSize(window_->window(), &width, &height);
      camera_.pan(delta.x, delta.y, float(height));
      break;
    }
    case MouseMode::Drag:
      updateDrag(cursor);
      break;
    case MouseMode::None:
      break;
  }
}

void Viewer::onScroll(double dy) {
  if (panelTakesMouse()) return;
  camera_.zoom(std::pow(kZoomPerNotch, float(dy)));
}

// A hidden panel's last answer may still say it has the pointer: it is not asked.
bool Viewer::panelTakesMouse() const {
  return panel_ && panel_shown_ && panel_->capturesMouse();
}

bool Viewer::panelTakesKeys() const {
  return panel_ && panel_shown_ && panel_->capturesKeyboard();
}

glm::vec2 Viewer::toFramebuffer(glm::vec2 cursor) const {
  int width = 0, height = 0;
  glfwGetWindowSize(window_->window(), &width, &height);
  const glm::ivec2 size = window_->framebufferSize();
  // On HiDPI screens the framebuffer has more pixels than the window has units.
  return width > 0 && height > 0 ? cursor * glm::vec2(size) / glm::vec2(float(width), float(height)) : cursor;
}

void Viewer::startDrag(glm::vec2 cursor) {
  if (!gpu_) {
    status_ = "dragging the cloth needs --solver gpu";
    return;
  }
  const glm::ivec2 size = window_->framebufferSize();
  const std::optional<PickHit> hit = renderer_.pick(cloth_buffers_, camera_, size, toFramebuffer(cursor));
  if (!hit) return;
  mouse_mode_ = MouseMode::Drag;
  drag_point_ = hit->point;
  // The point moves in the plane through it that faces the camera, following the cursor.
  drag_plane_point_ = hit->position;
  drag_plane_normal_ = glm::normalize(camera_.position() - camera_.target());
  gpu_->holdPoint(drag_point_, hit->position);
  status_ = "dragging point " + std::to_string(drag_point_);
}

void Viewer::updateDrag(glm::vec2 cursor) {
  if (!gpu_ || drag_point_ < 0) return;
  const Ray ray = camera_.rayThrough(toFramebuffer(cursor), window_->framebufferSize());
  const float denominator = glm::dot(ray.direction, drag_plane_normal_);
  if (std::abs(denominator) < 1e-6f) return;
  const float t = glm::dot(drag_plane_point_ - ray.origin, drag_plane_normal_) / denominator;
  if (t <= 0.0f) return;
  gpu_->holdPoint(drag_point_, ray.origin + t * ray.direction);
}

void Viewer::endDrag() {
  if (gpu_ && drag_point_ >= 0) gpu_->releasePoint();
  drag_point_ = -1;
  if (mouse_mode_ == MouseMode::Drag) mouse_mode_ = MouseMode::None;
}

}  // namespace drape
