#include "app/options.hpp"

#include "app/commands.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <regex>

namespace drape {

namespace {

std::string trimmed(const std::string& text) {
  const std::size_t first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

}  // namespace

CLI::Validator trimItem() {
  return CLI::Validator(
      [](std::string& item) {
        item = trimmed(item);
        return std::string();
      },
      "");
}

CLI::Validator numberCheck(const char* description, bool (*accept)(double)) {
  return CLI::Validator(
      [description, accept](std::string& value) {
        try {
          std::size_t used = 0;
          const double number = std::stod(value, &used);
          if (used == value.size() && accept(number)) return std::string();
        } catch (const std::exception&) {
        }
        return std::string("must be a number ") + description + ", got " + value;
      },
      description);
}

CLI::Validator integerIn(int min_value, int max_value) {
  return CLI::Validator(
      [min_value, max_value](const std::string& item) {
        std::size_t used = 0;
        long long value = 0;
        try {
          value = std::stoll(item, &used);
        } catch (const std::out_of_range&) {
          return fmt::format("{} is {} the {} {}", item, item[0] == '-' ? "below" : "above",
                             item[0] == '-' ? "minimum" : "maximum", item[0] == '-' ? min_value : max_value);
        } catch (const std::exception&) {
          used = 0;
        }
        if (item.empty() || used != item.size()) return fmt::format("'{}' is not an integer", item);
        if (value < min_value) return fmt::format("{} is below the minimum {}", value, min_value);
        if (value > max_value) return fmt::format("{} is above the maximum {}", value, max_value);
        return std::string();
      },
      fmt::format("INT in [{} .. {}]", min_value, max_value));
}

CLI::Validator positiveNumberUpTo(double max_value) {
  return CLI::Validator(
      [max_value](const std::string& item) {
        std::size_t used = 0;
        double value = 0;
        try {
          value = std::stod(item, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (item.empty() || used != item.size() || !std::isfinite(value) || value <= 0)
          return fmt::format("'{}' is not a positive number", item);
        if (value > max_value) return fmt::format("{} is above the maximum {:g}", item, max_value);
        return std::string();
      },
      fmt::format("NUMBER in (0 .. {:g}]", max_value));
}

std::vector<std::string> integratorNames() {
  std::vector<std::string> names;
  for (Integrator i : kIntegrators)
    names.push_back(integratorName(i));
  return names;
}

CLI::Option* addIntegratorOption(CLI::App* command, std::string& target) {
  return command
      ->add_option("--integrator", target,
                   "verlet (CS184's explicit Verlet), xpbd (springs as constraints) or vbd (Vertex Block Descent, "
                   "a Newton step per point); the last two are stable at any stiffness; default: the scene's "
                   "simulation.integrator")
      ->check(CLI::IsMember(integratorNames()));
}

void applyIntegrator(Scene& scene, const std::string& name) {
  if (name.empty()) return;
  for (Integrator i : kIntegrators)
    if (name == integratorName(i)) scene.sim.integrator = i;
}

glm::ivec2 parseSize(const std::string& option, const std::string& text, int min_side, int max_side) {
  static const std::regex pattern("([0-9]+)x([0-9]+)");
  std::smatch m;
  if (!std::regex_match(text, m, pattern))
    throw CommandError(kExitBadInput, fmt::format("{}: '{}' is not WIDTHxHEIGHT (e.g. 640x480)", option, text));
  // Any number of digits is a size, too large ones included: those are out of range, not malformed.
  const auto side = [](const std::string& digits) {
    const std::size_t first = std::min(digits.find_first_not_of('0'), digits.size() - 1);
    return digits.size() - first > 9 ? INT_MAX : std::stoi(digits.substr(first));
  };
  const glm::ivec2 size{side(m[1]), side(m[2])};
  if (size.x < min_side || size.y < min_side || size.x > max_side || size.y > max_side)
    throw CommandError(kExitBadInput, fmt::format("{}: {} is outside {}x{} .. {}x{}", option, text, min_side, min_side,
                                                  max_side, max_side));
  return size;
}

}  // namespace drape
