#include "app/commands.hpp"
#include "core/atomic_file.hpp"
#include "core/scene.hpp"

#include <fmt/core.h>

#include <cstdio>
#include <exception>
#include <string>

namespace {

std::string commandNames(const CLI::App& app) {
  std::string names;
  for (const CLI::App* command : app.get_subcommands({}))
    names += (names.empty() ? "" : ", ") + command->get_name();
  return names;
}

// CLI11 answers both `drape` and `drape frobnicate` with "A subcommand is required": name the word
// that is not a command, and list the commands.
std::string missingCommandMessage(const CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (argv[i][0] != '-')
      return fmt::format("unknown command '{}' (commands: {}; drape --help)", argv[i], commandNames(app));
  return fmt::format("a command is required: {} (drape --help)", commandNames(app));
}

// CLI11 says "--frames: At Most 1 required but received 2" for an option given twice.
std::string usageMessage(const CLI::ParseError& e) {
  const std::string text = e.what();
  const std::size_t at = text.find(": At Most 1 required but received ");
  return at == std::string::npos ? text : text.substr(0, at) + ": given more than once";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Drape: real-time mass-spring cloth simulation on the GPU (OpenGL compute)"};
  app.require_subcommand(1);
  drape::addSimulateCommand(app);
  drape::addViewCommand(app);
  drape::addRenderCommand(app);
  drape::addBenchCommand(app);
  drape::addAccuracyCommand(app);
  drape::addStabilityCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" that exit 0; usage errors are bad input: status 2, one line.
    if (e.get_exit_code() == 0) return app.exit(e);
    const bool no_command = app.get_subcommands().empty() && e.get_name() == "RequiredError";
    fmt::print(stderr, "drape: {}\n", no_command ? missingCommandMessage(app, argc, argv) : usageMessage(e));
    return drape::kExitBadInput;
  } catch (const drape::CommandError& e) {
    fmt::print(stderr, "drape: {}\n", e.what());
    return e.status();
  } catch (const drape::OutputError& e) {
    fmt::print(stderr, "drape: {}\n", e.what());
    return e.badTarget() ? drape::kExitBadInput : drape::kExitFailure;
  } catch (const drape::SceneError& e) {
    fmt::print(stderr, "drape: {}\n", e.what());
    return drape::kExitBadInput;
  } catch (const std::exception& e) {
    fmt::print(stderr, "drape: error: {}\n", e.what());
    return drape::kExitFailure;
  }
  return 0;
}
