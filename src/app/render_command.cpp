// `drape render`: run a scene headless (EGL, no display) and write frames as PNGs, optionally a video.
#include "app/commands.hpp"
#include "app/export.hpp"
#include "app/look_ahead.hpp"
#include "app/options.hpp"
#include "app/output.hpp"
#include "app/process.hpp"
#include "app/solver_factory.hpp"
#include "app/video.hpp"
#include "core/metrics.hpp"
#include "gl/context.hpp"
#include "render/image.hpp"
#include "render/renderer.hpp"

#include <fmt/core.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <optional>
#include <vector>

namespace drape {

namespace {

constexpr int kMaxRenderFrames = 1000000;

struct RenderOptions {
  std::string scene;
  int frames = 90;
  int every = 1;
  std::string out;
  std::vector<std::string> shader = {"phong"};
  std::string size = "640x480";
  std::string solver = "gpu";
  std::string video;
  std::string export_path;
  std::string export_format;
  int latitudes = 40;
  int longitudes = 40;
  int samples = 1;
  std::string camera = "scene";
  double zoom = 1.0;
  std::string integrator;  // empty: the scene's
};

// The --shader list (names checked by CLI11): "all" anywhere means every model, in their order.
std::vector<Shading> chosenShadings(const std::vector<std::string>& names) {
  if (std::find(names.begin(), names.end(), "all") != names.end()) return {allShadings().begin(), allShadings().end()};
  std::vector<Shading> shadings;
  for (const std::string& name : names) {
    const Shading shading = *parseShading(name);
    if (std::find(shadings.begin(), shadings.end(), shading) == shadings.end()) shadings.push_back(shading);
  }
  return shadings;
}

std::vector<std::string> shaderChoices() {
  std::vector<std::string> names;
  for (Shading shading : allShadings())
    names.emplace_back(shadingName(shading));
  names.emplace_back("all");
  return names;
}

// The frame's one read-back, as an RGB image (the alpha channel is always opaque).
Image readImage(const gl::Framebuffer& target) {
  const std::vector<std::uint8_t> rgba = target.readPixelsRGBA();
  Image image{target.width(), target.height(), 3, std::vector<std::uint8_t>(rgba.size() / 4 * 3)};
  for (std::size_t i = 0, n = rgba.size() / 4; i < n; ++i)
    for (int c = 0; c < 3; ++c)
      image.pixels[i * 3 + c] = rgba[i * 4 + c];
  return image;
}

// The video of each shading model: VIDEO itself for one; VIDEO's stem, the model's name and its
// extension for several (out.mp4 -> out_phong.mp4, out_toon.mp4).
std::vector<std::filesystem::path> videoPaths(const std::string& video, const std::vector<Shading>& shadings) {
  if (shadings.size() == 1) return {video};
  const std::filesystem::path given(video);
  std::vector<std::filesystem::path> paths;
  for (Shading shading : shadings)
    paths.push_back(given.parent_path() /
                    (given.stem().string() + "_" + std::string(shadingName(shading)) + given.extension().string()));
  return paths;
}

// An existing --out must be a directory; the directories are made only once everything else is known to
// work, so that a bad scene or a missing context leaves nothing behind.
void checkOutputDirectory(const std::filesystem::path& dir) {
  std::error_code error;
  const auto status = std::filesystem::status(dir, error);
  if (std::filesystem::exists(status) && !std::filesystem::is_directory(status))
    throw CommandError(kExitBadInput, fmt::format("--out: {} exists and is not a directory", dir.string()));
}

std::vector<std::filesystem::path> makeOutputDirectories(const RenderOptions& o, const std::vector<Shading>& shadings) {
  // One shader writes DIR/frame_NNNN.png; several write DIR/SHADER/frame_NNNN.png.
  std::vector<std::filesystem::path> dirs;
  for (Shading shading : shadings)
    dirs.push_back(shadings.size() == 1 ? std::filesystem::path(o.out)
                                        : std::filesystem::path(o.out) / shadingName(shading));
  for (const std::filesystem::path& dir : dirs) {
    std::error_code error;
    std::filesystem::create_directories(dir, error);
    if (error || !std::filesystem::is_directory(dir))
      throw CommandError(kExitBadInput, fmt::format("--out: cannot create directory {}: {}", dir.string(),
                                                    error ? error.message() : "not a directory"));
  }
  return dirs;
}

gl::HeadlessContext makeRenderContext() {
  try {
    return gl::HeadlessContext::create();
  } catch (const gl::ContextError& e) {
    throw CommandError(kExitNoGl, fmt::format("render: no OpenGL 4.5 context: {}", e.what()));
  }
}

void runRender(const RenderOptions& o) {
  const glm::ivec2 size = parseSize("--size", o.size, 16, 8192);
  const std::vector<Shading> shadings = chosenShadings(o.shader);
  if (!o.video.empty() && !findProgram("ffmpeg"))
    throw CommandError(kExitFailure, fmt::format("--video: ffmpeg is not installed (apt-get install ffmpeg); "
                                                 "leave out --video to write the PNG frames only"));
  checkOutputDirectory(o.out);
  const std::vector<std::filesystem::path> video_paths =
      o.video.empty() ? std::vector<std::filesystem::path>{} : videoPaths(o.video, shadings);
  for (const std::filesystem::path& video : video_paths)
    checkOutputFile(video);
  const ExportTarget export_target =
      o.export_path.empty() ? ExportTarget{} : resolveExport(o.export_path, o.export_format);
  Scene scene = loadScene(o.scene);
  applyIntegrator(scene, o.integrator);

  gl::HeadlessContext context = makeRenderContext();
  fmt::print(stderr, "render: {}\n", gl::describe(context.info()));
  if (const int most = gl::Framebuffer::maxSamples(); o.samples > most)
    throw CommandError(kExitBadInput, fmt::format("--samples: {} is more than this OpenGL allows ({}, "
                                                  "GL_MAX_SAMPLES on {})",
                                                  o.samples, most, context.info().renderer));
  // The GPU solver runs in the renderer's context and is drawn from there; CPU solvers need the context
  // for the renderer only.
  SolverFactory factory({.use_current_context = true});
  std::unique_ptr<Solver> solver = factory.make(scene, o.solver);
  ClothFeed feed(*solver);
  std::optional<ClothExport> exporter;
  if (!o.export_path.empty()) exporter.emplace(export_target, scene, solver->topology(), o.frames / o.every * o.every);
  // The default camera frames the whole run (at least the 2 s the viewer frames, so that the two agree),
  // and the floor, the light and the shadow map follow where the cloth goes; --camera start frames the
  // scene as it starts, without the look-ahead.
  const SceneExtent extent = o.camera != "start" ? lookAheadExtent(scene, solver->topology(),
                                                                   std::max(o.frames, lookAheadFrames(scene)), "render")
                                                 : SceneExtent(scene, solver->topology());
  Renderer renderer(scene, solver->topology(), extent,
                    {.sphere_latitudes = o.latitudes, .sphere_longitudes = o.longitudes});
  gl::Framebuffer target = gl::Framebuffer::createColorDepth(size.x, size.y, o.samples);
  // Each video's temporary is made before the first frame: a folder that cannot take the video fails now.
  std::vector<std::unique_ptr<VideoOutput>> videos;
  for (const std::filesystem::path& video : video_paths)
    videos.push_back(std::make_unique<VideoOutput>(video));
  const std::vector<std::filesystem::path> dirs = makeOutputDirectories(o, shadings);
  Camera camera;
  const float aspect = float(size.x) / float(size.y);
  camera.frame(renderer.framingSubject(), aspect);
  camera.zoom(float(o.zoom));
  RenderSettings settings;
  settings.springs = enabledSprings(scene.cloth);
  settings.light = renderer.defaultLight();

  const bool interactive = ::isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  std::string export_kept;  // set once a blow-up ended the export early
  int written = 0;
  std::vector<std::vector<std::filesystem::path>> frames_written(shadings.size());
  for (int frame = 0; frame <= o.frames; ++frame) {
    if (frame > 0) solver->stepFrame();
    if (frame % o.every != 0) continue;
    if (exporter && export_kept.empty()) {
      // A blown-up cloth is not exported: the export keeps the frames before it, the images go on.
      const std::vector<glm::dvec3> x = solver->readPositions();
      if (allFinite(x))
        exporter->add(frame, x);
      else
        export_kept = keepExport(*exporter);
    }
    if (o.camera == "cloth") {
      // Framing the cloth where it is now takes an explicit read-back of its positions, per image.
      const std::vector<glm::dvec3> x = solver->readPositions();
      Bounds bounds{glm::vec3(x.front()), glm::vec3(x.front())};
      for (const glm::dvec3& p : x)
        bounds.include(glm::vec3(p));
      camera.frame(bounds, aspect);
      camera.zoom(float(o.zoom));
    }
    const ClothBuffers cloth = feed.prepare();
    for (std::size_t k = 0; k < shadings.size(); ++k) {
      settings.shading = shadings[k];
      target.bind();
      renderer.draw(cloth, camera, size, settings);
      frames_written[k].push_back(dirs[k] / fmt::format("frame_{:04d}.png", frame));
      writePng(frames_written[k].back(), readImage(target));
      ++written;
    }
    // On a terminal the line updates in place; in a log only the final line appears.
    if (interactive || frame + o.every > o.frames) {
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      fmt::print(stderr, "{}render: frame {}/{}, {} image{} in {}, {:.1f} frames/s", interactive ? "\r" : "", frame,
                 o.frames, written, written == 1 ? "" : "s", o.out, frame / std::max(seconds, 1e-9));
    }
  }
  fmt::print(stderr, "\n");
  // One explicit read-back at the end: a cloth that blew up leaves empty pictures, which must not pass.
  if (!allFinite(solver->readPositions()))
    throw CommandError(kExitBlowUp, fmt::format("{}: the simulation became non-finite within {} frames; the images "
                                                "in {} show it{}",
                                                scene.path, o.frames, o.out, exporter ? keepExport(*exporter) : ""));
  if (exporter) exporter->finish();
  for (std::size_t k = 0; k < videos.size(); ++k)
    videos[k]->encode(frames_written[k], scene.sim.frames_per_sec / o.every);
}

}  // namespace

void addRenderCommand(CLI::App& app) {
  auto opts = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render a scene headless (no display needed) to PNG frames");
  cmd->add_option("scene", opts->scene, "Scene JSON file")->required();
  // Bounded so that frame + every cannot overflow an int (and frame_NNNN names stay short).
  cmd->add_option("--frames", opts->frames, "Frames to simulate; frame 0 is the initial state")
      ->check(CLI::Range(0, kMaxRenderFrames));
  cmd->add_option("--every", opts->every, "Write every K-th frame")->check(CLI::Range(1, kMaxRenderFrames));
  cmd->add_option("--out", opts->out, "Directory for frame_NNNN.png")->required();
  cmd->add_option("--export", opts->export_path,
                  "Also write the cloth per written frame: PATH_NNNN.obj or .ply, or one PATH.usda; a folder (DIR/) "
                  "gets cloth_NNNN.obj inside; missing folders are made");
  cmd->add_option("--format", opts->export_format,
                  "--export format: obj, ply or usda, which decides the files' extension (default: PATH's extension; "
                  "obj for a folder)")
      ->check(CLI::IsMember({"obj", "ply", "usda"}));
  addListOption(cmd, "--shader", opts->shader, "Shading models, comma-separated, or all")
      ->check(CLI::IsMember(shaderChoices()));
  cmd->add_option("--size", opts->size, "Image size WIDTHxHEIGHT");
  cmd->add_option("--solver", opts->solver,
                  "gpu (the path chosen for the device), gpu-general, gpu-tiled or gpu-onedispatch (forced), "
                  "cpu or cpu64")
      ->check(CLI::IsMember(solverNames(false)));
  addIntegratorOption(cmd, opts->integrator);
  cmd->add_option("--video", opts->video,
                  "Also encode the frames this run wrote into this video with ffmpeg (e.g. out.mp4; with several "
                  "shaders one video each, out_SHADER.mp4)");
  cmd->add_option("-a,--latitudes", opts->latitudes, "Sphere latitude rings")->check(CLI::Range(2, 1000));
  cmd->add_option("-o,--longitudes", opts->longitudes, "Sphere longitude segments")->check(CLI::Range(3, 1000));
  cmd->add_option("--samples", opts->samples, "Multisampling per pixel")->check(CLI::Range(1, 16));
  cmd->add_option("--camera", opts->camera,
                  "scene: one view of the scene and everywhere the cloth goes in the run (run once on the CPU "
                  "before the first image; at least 2 s of it, as `view` frames it); start: the scene as it "
                  "starts; cloth: the cloth where it is in each image")
      ->check(CLI::IsMember({"scene", "start", "cloth"}));
  cmd->add_option("--zoom", opts->zoom, "Camera distance factor (< 1 is closer)")->check(CLI::Range(0.01, 100.0));
  cmd->callback([opts] { runRender(*opts); });
}

}  // namespace drape
