#include "app/stability_summary.hpp"

#include "core/stability.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace drape {

double stabilityRunCost(const StabilityCase& c, int steps, bool guard) {
  Scene scene = c.scene;
  scene.sim.steps_per_frame = steps;
  const int substeps = guard ? std::max(steps, autoSubsteps(scene)) : steps;
  const double points = double(c.scene.cloth.num_width_points) * double(c.scene.cloth.num_height_points);
  const double factor = c.scene.sim.integrator == Integrator::Vbd ? 2.0 : 1.0;
  return double(c.frames) * substeps * points * factor;
}

namespace {

struct Row {
  Integrator integrator;
  int steps;
  bool guard;
};

// The runs of a row: with the guard, a case's guarded run where the guard raised its count, else its plain run.
std::vector<const StabilityResult*> rowRuns(const StabilityReport& report, const std::vector<StabilityCase>& cases,
                                            const Row& row) {
  std::vector<const StabilityResult*> runs;
  for (const StabilityCase& c : cases) {
    const StabilityResult* guarded = row.guard ? findResult(report, c.name, row.steps, true, row.integrator) : nullptr;
    if (const StabilityResult* r = guarded ? guarded : findResult(report, c.name, row.steps, false, row.integrator))
      runs.push_back(r);
  }
  return runs;
}

// The largest ks of the sweep whose run is `good` (stable, or keeps its shape).
template <class Good>
std::string largestKs(const std::vector<StabilityCase>& cases, const std::vector<const StabilityResult*>& runs,
                      Good good) {
  double best = 0;
  for (const StabilityResult* r : runs)
    for (const StabilityCase& c : cases)
      if (c.name == r->case_name && (c.sweeps_ks || c.implicit_only) && good(*r))
        best = std::max(best, c.scene.cloth.ks);
  if (best <= 0) return "none";
  // The sweep's stiffnesses are powers of ten: 1e6, not 1e+06.
  const double exponent = std::round(std::log10(best));
  return std::pow(10.0, exponent) == best ? fmt::format("1e{:g}", exponent) : fmt::format("{:g}", best);
}

}  // namespace

std::string stabilitySummary(const StabilityReport& report, const std::vector<StabilityCase>& cases) {
  std::vector<Row> rows;
  for (int s : report.steps) {
    rows.push_back({Integrator::Verlet, s, false});
    rows.push_back({Integrator::Verlet, s, true});
  }
  for (Integrator integrator : report.implicit)
    for (int s : report.implicit_steps)
      rows.push_back({integrator, s, false});
  std::string table =
      "| integrator | substeps | keeps its shape | stable | largest ks keeping its shape | largest stable ks | "
      "unstable (frame) |\n|---|---|---|---|---|---|---|\n";
  for (const Row& row : rows) {
    const std::vector<const StabilityResult*> runs = rowRuns(report, cases, row);
    if (runs.empty()) continue;
    std::vector<std::string> unstable;
    for (const StabilityResult* r : runs)
      if (!r->stable) unstable.push_back(fmt::format("{} ({})", r->case_name, r->first_bad_frame));
    const std::size_t stable = runs.size() - unstable.size();
    const auto shaped =
        std::count_if(runs.begin(), runs.end(), [](const StabilityResult* r) { return keepsShape(*r); });
    std::string shown = unstable.empty() ? "–" : "";
    for (std::size_t k = 0; k < unstable.size() && k < 3; ++k)
      shown += (k ? ", " : "") + unstable[k];
    if (unstable.size() > 3) shown += fmt::format(", {} more", unstable.size() - 3);
    table += fmt::format("| {} | {}{} | {} of {} | {} of {} | {} | {} | {} |\n", integratorName(row.integrator),
                         row.steps, row.guard ? " (guard)" : "", shaped, runs.size(), stable, runs.size(),
                         largestKs(cases, runs, keepsShape),
                         largestKs(cases, runs, [](const StabilityResult& r) { return r.stable; }), shown);
  }
  return table;
}

}  // namespace drape
