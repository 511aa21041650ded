#include "app/measure.hpp"

#include <fmt/format.h>
#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <fstream>
#include <thread>

namespace drape {

Scene resampleCloth(const Scene& scene, int n, bool keep_thickness) {
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
  if (!keep_thickness) c.thickness = std::min(c.thickness, 0.45 * spacing);
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

}  // namespace drape
