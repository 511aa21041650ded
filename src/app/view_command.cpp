// `drape view`: the interactive viewer (src/render/viewer.hpp) with its Dear ImGui control panel.
#include "app/commands.hpp"
#include "app/imgui_panel.hpp"
#include "app/look_ahead.hpp"
#include "app/options.hpp"
#include "app/solver_factory.hpp"
#include "core/data_dir.hpp"
#include "gl/context.hpp"
#include "gl/objects.hpp"
#include "render/viewer.hpp"

#include <GLFW/glfw3.h>
#include <fmt/core.h>
#include <fmt/format.h>

#include <filesystem>

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
  std::string integrator;  // empty: the scene's
  std::string camera = "scene";
};

// The default scene is found from the current directory or, failing that, among drape's own scenes.
std::string resolveScene(const std::string& scene) {
  if (!scene.empty()) return scene;
  const std::filesystem::path local = "scenes/sphere.json";
  if (std::filesystem::exists(local)) return local.string();
  return (dataDir("scenes") / "sphere.json").string();
}

void runView(const ViewOptions& o) {
  const glm::ivec2 size = parseSize("--size", o.size, 64, 8192);
  const std::optional<Shading> shading = parseShading(o.shader);
  if (!shading)
    throw CommandError(kExitBadInput, fmt::format("--shader: unknown shader '{}' ({})", o.shader, shadingNames()));
  Scene scene = loadScene(resolveScene(o.scene));
  applyIntegrator(scene, o.integrator);

  gl::WindowContext window;
  try {
    window = gl::WindowContext::create(size.x, size.y, "Drape - " + scene.path);
  } catch (const gl::ContextError& e) {
    throw CommandError(kExitNoGl, fmt::format("view: {} (without a display, `drape render` writes images)", e.what()));
  }
  fmt::print(stderr, "view: {}\n", gl::describe(window.info()));
  // The GPU solver runs in the window's context and times every pass for the panel with GPU timestamps,
  // which costs no wait. Without GPU timers (llvmpipe), timing would drain the pipeline around every
  // dispatch, so the panel shows dispatch counts only.
  SolverFactory factory({.use_current_context = true});
  std::unique_ptr<Solver> solver =
      factory.make(scene, o.solver, {.pass_timing = !isGpuSolver(o.solver) || gl::timerQueriesWork()});
  ViewerOptions options;
  options.renderer.sphere_latitudes = o.latitudes;
  options.renderer.sphere_longitudes = o.longitudes;
  options.shading = *shading;
  options.frames = o.frames;
  options.screenshot = o.screenshot;
  // The camera `render` has by default: the run's first frames, looked ahead on the CPU before the window
  // shows the scene, then following the cloth.
  options.follow = o.camera == "scene";
  if (o.camera == "scene") options.extent = lookAheadExtent(scene, solver->topology(), "view");
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
  cmd->add_option("-a,--latitudes", opts->latitudes, "Sphere latitude rings")->check(CLI::Range(2, 1000));
  cmd->add_option("-o,--longitudes", opts->longitudes, "Sphere longitude segments")->check(CLI::Range(3, 1000));
  cmd->add_option("--shader", opts->shader, "Shading model: " + shadingNames());
  cmd->add_option("--solver", opts->solver,
                  "gpu (the path chosen for the device), gpu-general, gpu-tiled or gpu-onedispatch (forced), "
                  "cpu or cpu64")
      ->check(CLI::IsMember(solverNames(false)));
  addIntegratorOption(cmd, opts->integrator);
  auto* frames =
      cmd->add_option(
             "--frames", opts->frames,
             "Simulate N frames, then close (with --screenshot: save the last); unset: until the window closes")
          ->check(kPositive)
          ->default_str("");  // 0 stands for unset
  cmd->add_option("--screenshot", opts->screenshot, "PNG of the last frame of a --frames run")->needs(frames);
  cmd->add_option("--size", opts->size, "Window size WIDTHxHEIGHT");
  cmd->add_option("--camera", opts->camera,
                  "scene: the scene and where the cloth goes in the run's first frames (looked ahead on the CPU "
                  "before the window opens), widening smoothly, never closer, wherever the cloth goes further: the "
                  "camera `render` has; start: the scene as it starts")
      ->check(CLI::IsMember({"scene", "start"}));
  cmd->footer(viewerControlsText());
  cmd->callback([opts] { runView(*opts); });
}

}  // namespace drape
