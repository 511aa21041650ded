#include "app/measure.hpp"

#include "app/commands.hpp"
#include "app/solver_factory.hpp"
#include "cpu/cpu_solver.hpp"
#include "gl/context.hpp"
#include "gl/objects.hpp"
#include "gpu/gpu_solver.hpp"

#include <fmt/format.h>
#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <fstream>
#include <sstream>
#include <thread>

namespace drape {

SolverFactory::SolverFactory() = default;

SolverFactory::~SolverFactory() = default;

std::unique_ptr<Solver> SolverFactory::make(const Scene& scene, const std::string& name, bool pass_timing,
                                            int threads) {
  if (name == "cpu" || name == "cpu64") return makeSolver(scene, name, false, threads);
  if (name == "cpu-xprev")
    return std::make_unique<CpuSolver<float>>(
        scene, CpuSolverOptions{.form = VerletForm::PreviousPosition, .threads = threads});
  if (name != "gpu")
    throw CommandError(kExitBadInput, fmt::format("unknown solver '{}' (cpu, cpu-xprev, cpu64, gpu)", name));
  if (!gpu_unavailable_.empty()) throw SkippedRun(gpu_unavailable_);
  if (!context_) {
    try {
      context_ = std::make_unique<gl::HeadlessContext>(gl::HeadlessContext::create());
    } catch (const std::exception& e) {
      gpu_unavailable_ = fmt::format("no OpenGL 4.5 context: {}", e.what());
      throw SkippedRun(gpu_unavailable_);
    }
  }
  context_->makeCurrent();
  GpuSolverOptions options;
  options.timing = pass_timing;
  std::unique_ptr<GpuSolver> solver;
  try {
    solver = std::make_unique<GpuSolver>(scene, options);
  } catch (const GpuLimitError& e) {
    throw SkippedRun(e.what());
  }
  if (gl_info_.renderer.empty()) {
    const gl::ContextInfo& info = context_->info();
    gl_info_ = {info.vendor,   info.renderer, info.version,          info.glsl_version,
                info.platform, info.software, gl::timerQueriesWork()};
  }
  return solver;
}

Scene resampleCloth(const Scene& scene, int n) {
  Scene out = scene;
  ClothSpec& c = out.cloth;
  const int W = scene.cloth.num_width_points, H = scene.cloth.num_height_points;
  c.num_width_points = n;
  c.num_height_points = n;
  c.pinned.clear();
  for (glm::ivec2 p : scene.cloth.pinned) {
    const glm::ivec2 q(int(std::lround(double(p.x) * (n - 1) / (W - 1))),
                       int(std::lround(double(p.y) * (n - 1) / (H - 1))));
    if (std::find(c.pinned.begin(), c.pinned.end(), q) == c.pinned.end()) c.pinned.push_back(q);
  }
  const double spacing = std::min(c.width, c.height) / double(n - 1);
  c.thickness = std::min(c.thickness, 0.45 * spacing);
  return out;
}

namespace {

std::string firstMatch(const char* file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key, 0) != 0) continue;
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string value = line.substr(colon + 1);
    value.erase(0, value.find_first_not_of(" \t"));
    return value;
  }
  return {};
}

double quantile(const std::vector<double>& sorted, double q) {
  const double pos = q * double(sorted.size() - 1);
  const std::size_t lo = std::size_t(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (pos - double(lo)) * (sorted[hi] - sorted[lo]);
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    out.push_back(item);
  }
  return out;
}

}  // namespace

std::string readLoadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  in >> one >> five >> fifteen;
  return in ? one + " " + five + " " + fifteen : std::string();
}

MachineInfo readMachineInfo() {
  MachineInfo m;
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) == 0) m.hostname = host;
  m.cpu_model = firstMatch("/proc/cpuinfo", "model name");
  m.logical_cores = int(std::thread::hardware_concurrency());
  const std::string mem = firstMatch("/proc/meminfo", "MemTotal");  // "24576000 kB"
  if (!mem.empty()) m.memory_bytes = std::atoll(mem.c_str()) * 1024;
  utsname u{};
  if (uname(&u) == 0) m.kernel = std::string(u.sysname) + " " + u.release + " " + u.machine;
  m.load_average = readLoadAverage();
  return m;
}

Spread summarize(std::vector<double> values) {
  Spread s;
  s.samples = int(values.size());
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  s.min = values.front();
  s.max = values.back();
  s.median = quantile(values, 0.5);
  s.q1 = quantile(values, 0.25);
  s.q3 = quantile(values, 0.75);
  return s;
}

std::string utcTimestamp() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::vector<int> parseIntList(const std::string& option, const std::string& text, int min_value, int max_value) {
  std::vector<int> out;
  for (const std::string& item : splitList(text)) {
    std::size_t used = 0;
    int value = 0;
    try {
      value = std::stoi(item, &used);
    } catch (const std::out_of_range&) {
      throw CommandError(kExitBadInput, fmt::format("{}: {} is above the maximum {}", option, item, max_value));
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used != item.size())
      throw CommandError(kExitBadInput, fmt::format("{}: '{}' is not an integer", option, item));
    if (value < min_value)
      throw CommandError(kExitBadInput, fmt::format("{}: {} is below the minimum {}", option, value, min_value));
    if (value > max_value)
      throw CommandError(kExitBadInput, fmt::format("{}: {} is above the maximum {}", option, value, max_value));
    out.push_back(value);
  }
  if (out.empty()) throw CommandError(kExitBadInput, fmt::format("{}: empty list", option));
  return out;
}

std::vector<double> parseDoubleList(const std::string& option, const std::string& text, double max_value) {
  std::vector<double> out;
  for (const std::string& item : splitList(text)) {
    std::size_t used = 0;
    double value = 0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used != item.size() || !std::isfinite(value) || value <= 0)
      throw CommandError(kExitBadInput, fmt::format("{}: '{}' is not a positive number", option, item));
    if (value > max_value)
      throw CommandError(kExitBadInput, fmt::format("{}: {} is above the maximum {:g}", option, item, max_value));
    out.push_back(value);
  }
  if (out.empty()) throw CommandError(kExitBadInput, fmt::format("{}: empty list", option));
  return out;
}

std::vector<std::string> parseNameList(const std::string& option, const std::string& text,
                                       const std::vector<std::string>& allowed) {
  std::vector<std::string> out = splitList(text);
  if (out.empty()) throw CommandError(kExitBadInput, fmt::format("{}: empty list", option));
  for (const std::string& name : out)
    if (name.empty() || (!allowed.empty() && std::find(allowed.begin(), allowed.end(), name) == allowed.end()))
      throw CommandError(kExitBadInput,
                         fmt::format("{}: unknown name '{}' (one of {})", option, name, fmt::join(allowed, ", ")));
  return out;
}

}  // namespace drape
