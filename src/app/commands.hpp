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

// Each returns nothing; the subcommand's callback throws CommandError on failure.
void addSimulateCommand(CLI::App& app);
void addViewCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addAccuracyCommand(CLI::App& app);
void addStabilityCommand(CLI::App& app);
void addPenetrationCommand(CLI::App& app);

}  // namespace drape
