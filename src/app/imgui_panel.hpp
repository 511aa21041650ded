// The viewer's control panel, in Dear ImGui: parameters (applied live, checked against the stability
// bound), appearance, per-pass timings and the keys. Lives in the app layer so that the viewer itself
// does not depend on the GUI library (render/viewer.hpp reaches it through ViewerPanel).
#pragma once

#include "render/viewer.hpp"

#include <glm/vec2.hpp>

#include <map>
#include <optional>
#include <string>

struct GLFWwindow;

namespace drape {

class ImGuiPanel final : public ViewerPanel {
 public:
  // Installs the GLFW and OpenGL 3 backends on `window`; create it after the Viewer, whose GLFW
  // callbacks the backend then chains to, and destroy it before.
  explicit ImGuiPanel(GLFWwindow* window);
  ~ImGuiPanel() override;
  ImGuiPanel(const ImGuiPanel&) = delete;
  ImGuiPanel& operator=(const ImGuiPanel&) = delete;

  void draw(Viewer& viewer) override;
  bool capturesMouse() const override;
  bool capturesKeyboard() const override;

  // Where each control was laid out in the last drawn frame, in window coordinates, by its label
  // ("ks (N/m)", "damping (%)", "self-collision", ...). Lets tests click the real widgets.
  struct Rect {
    glm::vec2 min{0.0f}, max{0.0f};  // the whole item, its label included
    float frame_width = 0.0f;        // of the slider or field itself, from min.x (sliders, drags)
    glm::vec2 centre() const { return 0.5f * (min + max); }
  };
  std::optional<Rect> controlRect(const std::string& label) const;

  // Replaces the pointer the GLFW backend polls (glfwGetCursorPos, glfwGetMouseButton) from the next
  // frame on; std::nullopt gives it back. A window under Xvfb has no pointer a test could move.
  struct Pointer {
    glm::vec2 position{0.0f};
    bool left_down = false;
  };
  void overridePointer(std::optional<Pointer> pointer) { pointer_ = pointer; }

 private:
  void drawControls(Viewer& viewer);
  void drawParameters(Viewer& viewer);
  void drawAppearance(Viewer& viewer);
  void drawPerformance(const Viewer& viewer);
  bool track(bool changed, const char* label);  // records the last item's rect under `label`

  std::map<std::string, Rect> rects_;
  std::optional<Pointer> pointer_;
};

}  // namespace drape
