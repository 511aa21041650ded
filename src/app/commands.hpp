// The `drape` subcommands. Each lives in its own file and registers itself on the CLI11 app; main.cpp
// is wiring only.
#pragma once

#include "app/command_error.hpp"

namespace CLI {
class App;
}

namespace drape {

// Each returns nothing; the subcommand's callback throws CommandError on failure.
void addSimulateCommand(CLI::App& app);
void addViewCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addAccuracyCommand(CLI::App& app);
void addStabilityCommand(CLI::App& app);
void addPenetrationCommand(CLI::App& app);

}  // namespace drape
