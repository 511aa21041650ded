// The `drape` subcommands. Each lives in its own file and registers itself on the CLI11 app; main.cpp
// is wiring only.
#pragma once

#include <CLI/CLI.hpp>

#include <memory>
#include <stdexcept>
#include <string>

namespace drape {

struct Scene;
class Solver;

// Exit statuses shared by every command.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;   // anything unexpected
inline constexpr int kExitBadInput = 2;  // scene file, option values
inline constexpr int kExitNoGl = 3;      // no OpenGL 4.5 context for --solver gpu / render / view
inline constexpr int kExitBlowUp = 4;    // the simulation became non-finite or ran away

// Thrown by commands to leave with a given status and one line on stderr.
class CommandError : public std::runtime_error {
 public:
  CommandError(int status, const std::string& message) : std::runtime_error(message), status_(status) {}
  int status() const { return status_; }

 private:
  int status_;
};

// Option checks with a short message ("must be a number > 0, got -3"): CLI11's NonNegativeNumber and
// PositiveNumber print their open end as DBL_MAX, all 310 digits of it.
inline CLI::Validator numberCheck(const char* description, bool (*accept)(double)) {
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
inline const CLI::Validator kNonNegative = numberCheck(">= 0", [](double v) { return v >= 0; });
inline const CLI::Validator kPositive = numberCheck("> 0", [](double v) { return v > 0; });

// Each returns nothing; the subcommand's callback throws CommandError on failure.
void addSimulateCommand(CLI::App& app);
void addViewCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addAccuracyCommand(CLI::App& app);
void addStabilityCommand(CLI::App& app);

}  // namespace drape
