#include "app/imgui_panel.hpp"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <string>

namespace drape {

namespace {

bool sliderDouble(const char* label, double& value, double min, double max, const char* format,
                  ImGuiSliderFlags flags) {
  return ImGui::SliderScalar(label, ImGuiDataType_Double, &value, &min, &max, format, flags);
}

bool dragVector(const char* label, glm::dvec3& value, float speed) {
  glm::vec3 v(value);
  if (!ImGui::DragFloat3(label, &v.x, speed)) return false;
  value = glm::dvec3(v);
  return true;
}

void drawHelp() {
  static const std::string text = viewerControlsText();
  ImGui::TextUnformatted(text.c_str());
}

}  // namespace

ImGuiPanel::ImGuiPanel(GLFWwindow* window) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the user's directory
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 450 core");
}

ImGuiPanel::~ImGuiPanel() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

bool ImGuiPanel::capturesMouse() const {
  return ImGui::GetIO().WantCaptureMouse;
}

bool ImGuiPanel::capturesKeyboard() const {
  return ImGui::GetIO().WantCaptureKeyboard;
}

std::optional<ImGuiPanel::Rect> ImGuiPanel::controlRect(const std::string& label) const {
  const auto it = rects_.find(label);
  if (it == rects_.end()) return std::nullopt;
  return it->second;
}

bool ImGuiPanel::track(bool changed, const char* label) {
  const ImVec2 min = ImGui::GetItemRectMin(), max = ImGui::GetItemRectMax();
  rects_[label] = Rect{{min.x, min.y}, {max.x, max.y}, ImGui::CalcItemWidth()};
  return changed;
}

void ImGuiPanel::draw(Viewer& viewer) {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  if (pointer_) {
    // After the backend polled the real pointer, before ImGui reads it.
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = ImVec2(pointer_->position.x, pointer_->position.y);
    io.MouseDown[0] = pointer_->left_down;
  }
  ImGui::NewFrame();
  rects_.clear();
  // Narrow and short by default (the parameters open, the look and the timings folded), over the top-left
  // corner, which the default camera leaves to the sky; H hides it.
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  // As tall as what is open, within the window: a section opened later grows it, a long one scrolls.
  const float font = ImGui::GetFontSize();
  ImGui::SetNextWindowSizeConstraints(ImVec2(font * 23, 0), ImVec2(font * 23, ImGui::GetIO().DisplaySize.y - 16));
  ImGui::SetNextWindowBgAlpha(0.8f);
  ImGui::Begin("Drape (H hides this)", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
  ImGui::PushItemWidth(ImGui::GetFontSize() * 10);  // leaves room for the labels on the right
  drawControls(viewer);
  if (ImGui::CollapsingHeader("Cloth and simulation", ImGuiTreeNodeFlags_DefaultOpen)) drawParameters(viewer);
  if (ImGui::CollapsingHeader("Appearance")) drawAppearance(viewer);
  if (ImGui::CollapsingHeader("Performance")) drawPerformance(viewer);
  if (ImGui::CollapsingHeader("Keys and mouse")) drawHelp();
  ImGui::PopItemWidth();
  ImGui::End();
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

void ImGuiPanel::drawControls(Viewer& viewer) {
  if (track(ImGui::Button(viewer.paused() ? "Resume (P)" : "Pause (P)"), "pause")) viewer.setPaused(!viewer.paused());
  ImGui::SameLine();
  if (track(ImGui::Button("Step (N)"), "step") && viewer.paused()) viewer.stepOnce();
  ImGui::SameLine();
  if (track(ImGui::Button("Reset (R)"), "reset")) viewer.resetCloth();
  if (ImGui::Button("Camera (Space)")) viewer.resetCamera();
  ImGui::SameLine();
  if (ImGui::Button("Screenshot (S)")) viewer.requestScreenshot();
  ImGui::Text("frame %lld, t = %.3f s, %.0f frames/s", viewer.framesSimulated(), viewer.solver().time(),
              viewer.stats().fps);
  const ImVec4 red(1.0f, 0.4f, 0.4f, 1.0f);
  if (!viewer.blowUp().empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, red);
    ImGui::TextWrapped("%s", viewer.status().c_str());
    ImGui::PopStyleColor();
  } else if (!viewer.status().empty()) {
    ImGui::TextWrapped("%s", viewer.status().c_str());
  }
  if (!viewer.shaderErrors().empty()) ImGui::TextColored(red, "%s", viewer.shaderErrors().c_str());
}

void ImGuiPanel::drawParameters(Viewer& viewer) {
  ClothSpec& c = viewer.cloth;
  SimParams& s = viewer.sim;
  bool changed = false;
  changed |= track(ImGui::Checkbox("structural", &c.enable_structural), "structural");
  ImGui::SameLine();
  changed |= track(ImGui::Checkbox("shearing", &c.enable_shearing), "shearing");
  ImGui::SameLine();
  changed |= track(ImGui::Checkbox("bending", &c.enable_bending), "bending");
  changed |= track(sliderDouble("ks (N/m)", c.ks, 1.0, 1e5, "%.0f", ImGuiSliderFlags_Logarithmic), "ks (N/m)");
  // CS184 shows density in g/cm^2: 1 kg/m^2 = 0.1 g/cm^2.
  double grams = c.density * 0.1;
  if (track(sliderDouble("density (g/cm^2)", grams, 0.01, 100.0, "%.2f", ImGuiSliderFlags_Logarithmic),
            "density (g/cm^2)")) {
    c.density = grams * 10.0;
    changed = true;
  }
  changed |= track(sliderDouble("damping (%)", c.damping, 0.0, 1.0, "%.3f", 0), "damping (%)");
  changed |= track(sliderDouble("frames/s", s.frames_per_sec, 10.0, 240.0, "%.0f", 0), "frames/s");
  changed |= track(ImGui::SliderInt("steps/frame", &s.steps_per_frame, 1, 200), "steps/frame");
  changed |= track(dragVector("gravity (m/s^2)", s.gravity, 0.1f), "gravity (m/s^2)");
  changed |= track(ImGui::Checkbox("self-collision", &s.self_collision), "self-collision");
  ImGui::SameLine();
  changed |= track(ImGui::Checkbox("wind", &s.wind.enabled), "wind");
  ImGui::SameLine();
  changed |= track(ImGui::Checkbox("tethers", &s.tethers), "tethers");
  if (s.wind.enabled) {
    changed |= track(dragVector("wind (m/s)", s.wind.velocity, 0.05f), "wind (m/s)");
    changed |= track(sliderDouble("turbulence", s.wind.turbulence, 0.0, 2.0, "%.2f", 0), "turbulence");
  }
  changed |= track(ImGui::SliderInt("stretch passes", &s.stretch_passes, 0, 10), "stretch passes");
  // Verlet, XPBD or VBD, switched live: all run on the same state (x and x - x_prev).
  for (Integrator i : kIntegrators) {
    if (i != Integrator::Verlet) ImGui::SameLine();
    if (track(ImGui::RadioButton(integratorName(i), s.integrator == i), integratorName(i))) {
      s.integrator = i;
      changed = true;
    }
  }
  if (isImplicit(s.integrator)) changed |= track(ImGui::SliderInt("iterations", &s.iterations, 1, 10), "iterations");
  if (changed) viewer.applyParams();

  // The explicit-integration bound of what is set now (core/stability.hpp), and the way back inside it.
  const StabilityCheck& check = viewer.stability();
  const ImVec4 colour = check.ok ? ImVec4(0.5f, 0.85f, 0.5f, 1.0f) : ImVec4(1.0f, 0.4f, 0.4f, 1.0f);
  ImGui::PushTextWrapPos(0.0f);  // within the panel's width
  if (isImplicit(s.integrator))
    ImGui::TextColored(colour, "%s: no explicit bound (Verlet's dt sqrt(k/m) = %.3g)", integratorName(s.integrator),
                       check.number);
  else
    ImGui::TextColored(colour, "dt sqrt(k/m) = %.3g, stable below %.3g", check.number, check.limit);
  ImGui::PopTextWrapPos();
  if (!check.ok && check.steps_needed > 0 && check.steps_needed <= 10000) {
    const std::string label = "use " + std::to_string(check.steps_needed) + " steps/frame";
    if (track(ImGui::Button(label.c_str()), "auto substeps")) {
      s.steps_per_frame = check.steps_needed;
      viewer.applyParams();
    }
  }
}

void ImGuiPanel::drawAppearance(Viewer& viewer) {
  RenderSettings& r = viewer.settings;
  if (ImGui::Button("Reload shaders (F5)")) viewer.reloadShaders();
  const std::string current(shadingName(r.shading));
  if (ImGui::BeginCombo("shader", current.c_str())) {
    for (Shading option : allShadings()) {
      const std::string name(shadingName(option));
      if (ImGui::Selectable(name.c_str(), option == r.shading)) r.shading = option;
    }
    ImGui::EndCombo();
  }
  track(false, "shader");
  ImGui::ColorEdit3("cloth colour", &r.cloth_colour.x);
  switch (r.shading) {
    case Shading::Phong:
    case Shading::Shadow:
      ImGui::Checkbox("ambient", &r.phong_terms[0]);
      ImGui::SameLine();
      ImGui::Checkbox("diffuse", &r.phong_terms[1]);
      ImGui::SameLine();
      ImGui::Checkbox("specular", &r.phong_terms[2]);
      break;
    case Shading::Bump:
    case Shading::Displacement: {
      ImGui::SliderFloat("normal scaling", &r.normal_scaling, 0.0f, 100.0f);
      ImGui::SliderFloat("height scaling (m)", &r.height_scaling, 0.0f, 0.1f, "%.4f");
      int map = int(r.height_map);
      if (ImGui::Combo("height map", &map, "cobblestone\0brick\0")) r.height_map = HeightMap(map);
      break;
    }
    case Shading::Toon:
      ImGui::SliderInt("bands", &r.toon_levels, 2, 8);
      break;
    case Shading::Mirror:
      ImGui::Checkbox("sky background", &r.sky);
      break;
    default:
      break;
  }
  ImGui::DragFloat3("light position (m)", &r.light.position.x, 0.02f);
  ImGui::DragFloat3("light intensity", &r.light.intensity.x, 0.05f, 0.0f, 100.0f);
  ImGui::Checkbox("show colliders", &r.show_colliders);
  ImGui::SameLine();
  ImGui::Checkbox("floor", &r.floor);
  ImGui::SameLine();
  ImGui::Checkbox("shadows", &r.shadows);
}

void ImGuiPanel::drawPerformance(const Viewer& viewer) {
  const ViewerStats& st = viewer.stats();
  ImGui::Text("%.1f frames/s, %.2f ms per frame", st.fps, st.frame_ms);
  ImGui::Text("simulate %.2f ms, draw %.2f ms", st.simulate_ms, st.draw_ms);
  ImGui::Text("per frame:");
  for (const ViewerStats::Pass& p : st.passes) {
    if (st.pass_ms) {
      ImGui::BulletText("%s: %.3f ms, %.0f calls", p.name.c_str(), p.ms, p.calls_per_frame);
    } else {
      ImGui::BulletText("%s: %.0f calls", p.name.c_str(), p.calls_per_frame);
    }
  }
  if (!st.pass_ms)
    ImGui::TextWrapped(
        "No pass times: this device has no GPU timer, and timing without one would stall every dispatch.");
  ImGui::TextWrapped("%s", gl::describe(viewer.contextInfo()).c_str());
}

}  // namespace drape
