// Option parsing the commands share: the number checks, comma-separated lists and WIDTHxHEIGHT sizes.
// A bad value is one line naming the option and exit status 2, like every usage error (docs/exit-status.md).
#pragma once

#include "app/option_values.hpp"

#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <vector>

namespace drape {

// Option checks with a short message ("must be a number > 0, got -3"): CLI11's NonNegativeNumber and
// PositiveNumber print their open end as DBL_MAX, all 310 digits of it.
CLI::Validator numberCheck(const char* description, bool (*accept)(double));
inline const CLI::Validator kNonNegative = numberCheck(">= 0", [](double v) { return v >= 0; });
inline const CLI::Validator kPositive = numberCheck("> 0", [](double v) { return v > 0; });

// Checks for one item of a list: "'x' is not an integer", "1 is below the minimum 2", "4096 is above
// the maximum 2048", "'-1' is not a positive number". CLI::Range says neither which end was crossed
// nor, for a double, anything shorter than DBL_MAX. Spaces around an item are dropped.
CLI::Validator integerIn(int min_value, int max_value);
CLI::Validator positiveNumberUpTo(double max_value);

// Drops spaces around a list item; describes nothing in --help.
CLI::Validator trimItem();

// A comma-separated list option ("--sizes 32,64,128"), split by CLI11's delimiter; each item is checked
// by what the caller adds (->check(integerIn(...)), ->check(CLI::IsMember(...)), which --help shows).
// Given twice, it is a usage error ("--sizes: given more than once"), as for every other option; empty
// items between commas are dropped by CLI11, a list with no item is an error. `target` keeps its value
// (the default --help shows) unless the option is given.
template <class T>
CLI::Option* addListOption(CLI::App* command, const std::string& name, std::vector<T>& target,
                           const std::string& description) {
  auto given = std::make_shared<int>(0);
  CLI::Option* option = command->add_option_function<std::vector<T>>(
      name,
      [&target, given, first = name.substr(0, name.find(','))](const std::vector<T>& values) {
        if (++*given > 1) throw CLI::ValidationError(first, "given more than once");
        target = values;
      },
      description);
  // One argument per occurrence, split at commas: "--steps 5 scene.json" leaves the scene positional.
  // trigger_on_parse runs the callback at each occurrence, which is how a second one is seen.
  option->delimiter(',')->allow_extra_args(false)->trigger_on_parse();
  option->transform(trimItem());  // first, so that the caller's checks see "64" in "32, 64"
  std::vector<std::string> shown;
  for (const T& value : target)
    shown.push_back(CLI::detail::to_string(value));
  option->default_str(CLI::detail::join(shown, ","));
  return option;
}

// --integrator verlet|xpbd|vbd into `target` (applyIntegrator applies it).
CLI::Option* addIntegratorOption(CLI::App* command, std::string& target);

}  // namespace drape
