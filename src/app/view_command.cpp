// `drape view`: the interactive viewer (src/render/viewer.hpp) with its Dear ImGui control panel.
#include "app/commands.hpp"
#include "app/solver_factory.hpp"
#include "gl/context.hpp"
#include "gpu/gpu_solver.hpp"
#include "render/viewer.hpp"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <fmt/core.h>
#include <fmt/format.h>
#include <imgui.h>

#include <filesystem>
#include <regex>

namespace drape {

namespace {

struct ViewOptions {
  std::string scene;
  int latitudes = 40;
  int longitudes = 40;
  std::string shader = "phong";
  std::string solver = "gpu";
  int frames = 0;
  std::string screenshot;
  std::string size = "1280x800";
};

// The panel: parameters (applied live), appearance, timings, and the keys.
class ImGuiPanel final : public ViewerPanel {
 public:
  explicit ImGuiPanel(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the user's directory
    ImGui::StyleColorsDark();
    // Installed after the viewer's callbacks, which the backend then calls after its own.
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 450 core");
  }
  ~ImGuiPanel() override {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  ImGuiPanel(const ImGuiPanel&) = delete;
  ImGuiPanel& operator=(const ImGuiPanel&) = delete;

  bool capturesMouse() const override { return ImGui::GetIO().WantCaptureMouse; }
  bool capturesKeyboard() const override { return ImGui::GetIO().WantCaptureKeyboard; }

  void draw(Viewer& viewer) override {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(440, 0), ImGuiCond_FirstUseEver);
    ImGui::Begin("Drape");
    ImGui::PushItemWidth(ImGui::GetFontSize() * 16);  // leaves room for the labels on the right
    drawControls(viewer);
    if (ImGui::CollapsingHeader("Cloth and simulation", ImGuiTreeNodeFlags_DefaultOpen)) drawParameters(viewer);
    if (ImGui::CollapsingHeader("Appearance", ImGuiTreeNodeFlags_DefaultOpen)) drawAppearance(viewer.settings);
    if (ImGui::CollapsingHeader("Performance", ImGuiTreeNodeFlags_DefaultOpen)) drawPerformance(viewer);
    if (ImGui::CollapsingHeader("Keys and mouse")) drawHelp();
    ImGui::PopItemWidth();
    ImGui::End();
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  }

 private:
  static void drawControls(Viewer& viewer) {
    if (ImGui::Button(viewer.paused() ? "Resume (P)" : "Pause (P)")) viewer.setPaused(!viewer.paused());
    ImGui::SameLine();
    if (ImGui::Button("Step (N)") && viewer.paused()) viewer.stepOnce();
    ImGui::SameLine();
    if (ImGui::Button("Reset (R)")) viewer.resetCloth();
    if (ImGui::Button("Camera (Space)")) viewer.resetCamera();
    ImGui::SameLine();
    if (ImGui::Button("Screenshot (S)")) viewer.requestScreenshot();
    ImGui::SameLine();
    if (ImGui::Button("Reload shaders (F5)")) viewer.reloadShaders();
    ImGui::Text("frame %lld, t = %.3f s", viewer.framesSimulated(), viewer.solver().time());
    if (!viewer.status().empty()) ImGui::TextWrapped("%s", viewer.status().c_str());
    if (!viewer.shaderErrors().empty())
      ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.4f, 1.0f), "%s", viewer.shaderErrors().c_str());
  }

  static void drawParameters(Viewer& viewer) {
    ClothSpec& c = viewer.cloth;
    SimParams& s = viewer.sim;
    bool changed = false;
    changed |= ImGui::Checkbox("structural", &c.enable_structural);
    ImGui::SameLine();
    changed |= ImGui::Checkbox("shearing", &c.enable_shearing);
    ImGui::SameLine();
    changed |= ImGui::Checkbox("bending", &c.enable_bending);
    changed |= sliderDouble("ks (N/m)", c.ks, 1.0, 1e5, "%.0f", ImGuiSliderFlags_Logarithmic);
    // CS184 shows density in g/cm^2: 1 kg/m^2 = 0.1 g/cm^2.
    double grams = c.density * 0.1;
    if (sliderDouble("density (g/cm^2)", grams, 0.01, 100.0, "%.2f", ImGuiSliderFlags_Logarithmic)) {
      c.density = grams * 10.0;
      changed = true;
    }
    changed |= sliderDouble("damping (%)", c.damping, 0.0, 1.0, "%.3f", 0);
    changed |= sliderDouble("frames/s", s.frames_per_sec, 10.0, 240.0, "%.0f", 0);
    changed |= ImGui::SliderInt("steps/frame", &s.steps_per_frame, 1, 200);
    changed |= dragVector("gravity (m/s^2)", s.gravity, 0.1f);
    changed |= ImGui::Checkbox("self-collision", &s.self_collision);
    ImGui::SameLine();
    changed |= ImGui::Checkbox("wind", &s.wind.enabled);
    if (s.wind.enabled) {
      changed |= dragVector("wind (m/s)", s.wind.velocity, 0.05f);
      changed |= sliderDouble("turbulence", s.wind.turbulence, 0.0, 2.0, "%.2f", 0);
    }
    changed |= ImGui::SliderInt("stretch passes", &s.stretch_passes, 0, 10);
    if (changed) viewer.applyParams();
  }

  static void drawAppearance(RenderSettings& r) {
    int shading = int(r.shading);
    const std::string current(shadingName(r.shading));
    if (ImGui::BeginCombo("shader", current.c_str())) {
      for (Shading option : allShadings()) {
        const std::string name(shadingName(option));
        if (ImGui::Selectable(name.c_str(), int(option) == shading)) r.shading = option;
      }
      ImGui::EndCombo();
    }
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
  }

  static void drawPerformance(const Viewer& viewer) {
    const ViewerStats& st = viewer.stats();
    ImGui::Text("%.1f frames/s, %.2f ms per frame", st.fps, st.frame_ms);
    ImGui::Text("simulate %.2f ms, draw %.2f ms", st.simulate_ms, st.draw_ms);
    ImGui::Text("per frame:");
    for (const ViewerStats::Pass& p : st.passes)
      ImGui::BulletText("%s: %.3f ms, %.0f calls", p.name.c_str(), p.ms, p.calls_per_frame);
    ImGui::TextWrapped("%s", gl::describe(viewer.contextInfo()).c_str());
  }

  static void drawHelp() {
    ImGui::TextWrapped(
        "P pause/resume, N one frame while paused, R reset the cloth, Space reset the camera, S screenshot, "
        "F5 reload shaders, Esc quit.\nLeft-drag orbit, right-drag or Ctrl+left-drag pan, scroll zoom, "
        "Shift+left-drag pull the cloth (GPU solver).");
  }

  static bool sliderDouble(const char* label, double& value, double min, double max, const char* format,
                           ImGuiSliderFlags flags) {
    return ImGui::SliderScalar(label, ImGuiDataType_Double, &value, &min, &max, format, flags);
  }

  static bool dragVector(const char* label, glm::dvec3& value, float speed) {
    glm::vec3 v(value);
    if (!ImGui::DragFloat3(label, &v.x, speed)) return false;
    value = glm::dvec3(v);
    return true;
  }
};

glm::ivec2 parseWindowSize(const std::string& text) {
  static const std::regex pattern("([0-9]{1,5})x([0-9]{1,5})");
  std::smatch m;
  if (!std::regex_match(text, m, pattern))
    throw CommandError(kExitBadInput, fmt::format("--size: '{}' is not WIDTHxHEIGHT (e.g. 1280x800)", text));
  const glm::ivec2 size{std::stoi(m[1]), std::stoi(m[2])};
  if (size.x < 64 || size.y < 64 || size.x > 8192 || size.y > 8192)
    throw CommandError(kExitBadInput, fmt::format("--size: {} is outside 64x64 .. 8192x8192", text));
  return size;
}

// The default scene is found from the current directory or, failing that, in the source tree.
std::string resolveScene(const std::string& scene) {
  if (!scene.empty()) return scene;
  const std::filesystem::path local = "scenes/sphere.json";
  if (std::filesystem::exists(local)) return local.string();
  return (std::filesystem::path(DRAPE_SOURCE_DIR) / local).string();
}

void runView(const ViewOptions& o) {
  const glm::ivec2 size = parseWindowSize(o.size);
  const std::optional<Shading> shading = parseShading(o.shader);
  if (!shading)
    throw CommandError(kExitBadInput, fmt::format("--shader: unknown shader '{}' ({})", o.shader, shadingNames()));
  const Scene scene = loadScene(resolveScene(o.scene));

  gl::WindowContext window;
  try {
    window = gl::WindowContext::create(size.x, size.y, "Drape - " + scene.path);
  } catch (const gl::ContextError& e) {
    throw CommandError(kExitNoGl, fmt::format("view: {} (without a display, `drape render` writes images)", e.what()));
  }
  fmt::print(stderr, "view: {}\n", gl::describe(window.info()));
  // The GPU solver times every pass for the panel; where timer queries work this costs nothing.
  std::unique_ptr<Solver> solver = o.solver == "gpu"
                                       ? std::make_unique<GpuSolver>(scene, GpuSolverOptions{.timing = true})
                                       : makeSolver(scene, o.solver);
  ViewerOptions options;
  options.renderer.sphere_latitudes = o.latitudes;
  options.renderer.sphere_longitudes = o.longitudes;
  options.shading = *shading;
  options.frames = o.frames;
  options.screenshot = o.screenshot;
  Viewer viewer(window, std::move(solver), options);
  // Created after the viewer (its callbacks chain to the viewer's) and destroyed before it.
  ImGuiPanel panel(window.window());
  viewer.run(&panel);
}

}  // namespace

void addViewCommand(CLI::App& app) {
  auto opts = std::make_shared<ViewOptions>();
  CLI::App* cmd = app.add_subcommand("view", "Interactive viewer (needs a display; see `drape render` otherwise)");
  cmd->add_option("scene", opts->scene, "Scene JSON file (default scenes/sphere.json)");
  cmd->add_option("-a,--latitudes", opts->latitudes, "Sphere latitude rings (default 40)")->check(CLI::Range(2, 1000));
  cmd->add_option("-o,--longitudes", opts->longitudes, "Sphere longitude segments (default 40)")
      ->check(CLI::Range(3, 1000));
  cmd->add_option("--shader", opts->shader, "Shading model: " + shadingNames());
  cmd->add_option("--solver", opts->solver, "gpu (default), cpu or cpu64")
      ->check(CLI::IsMember({"cpu", "cpu64", "gpu"}));
  auto* frames =
      cmd->add_option("--frames", opts->frames, "Simulate N frames, then close (with --screenshot: save the last)")
          ->check(CLI::PositiveNumber);
  cmd->add_option("--screenshot", opts->screenshot, "PNG of the last frame of a --frames run")->needs(frames);
  cmd->add_option("--size", opts->size, "Window size WIDTHxHEIGHT (default 1280x800)");
  cmd->callback([opts] { runView(*opts); });
}

}  // namespace drape
