#include "app/commands.hpp"
#include "app/suggest.hpp"
#include "core/atomic_file.hpp"
#include "core/data_dir.hpp"
#include "core/memory_stage.hpp"
#include "core/scene.hpp"

#include <fmt/core.h>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <string>
#include <string_view>
#include <vector>

namespace {

std::string commandNames(const CLI::App& app) {
  std::string names;
  for (const CLI::App* command : app.get_subcommands({}))
    names += (names.empty() ? "" : ", ") + command->get_name();
  return names;
}

// CLI11 answers both `drape` and `drape frobnicate` with "A subcommand is required": name the word
// that is not a command (and the command it may be a slip for), or the option drape does not know, and list
// the commands.
std::string missingCommandMessage(const CLI::App& app, int argc, const char* const* argv) {
  std::vector<std::string> commands;
  for (const CLI::App* command : app.get_subcommands({}))
    commands.push_back(command->get_name());
  for (int i = 1; i < argc; ++i)
    if (argv[i][0] != '-') {
      const std::string near = drape::closestWord(argv[i], commands);
      return fmt::format("unknown command '{}' ({}commands: {}; drape --help)", argv[i],
                         near.empty() ? "" : "did you mean " + near + "? ", commandNames(app));
    }
  const std::string unknown = drape::unknownOptionMessage(app, std::vector<std::string>(argv + 1, argv + argc));
  if (!unknown.empty()) return fmt::format("{} (commands: {}; drape --help)", unknown, commandNames(app));
  return fmt::format("a command is required: {} (drape --help)", commandNames(app));
}

// An option the command does not have: say which, and the one it may be a slip for, instead of CLI11's
// "The following argument was not expected".
std::string extrasMessage(const CLI::App& app, const CLI::ParseError& e, int argc, const char* const* argv) {
  const std::vector<CLI::App*> chosen = app.get_subcommands();
  const CLI::App& command = chosen.empty() ? app : *chosen.back();
  std::vector<std::string> args;
  bool after = chosen.empty();  // the command's own arguments follow its name
  for (int i = 1; i < argc; ++i) {
    if (after) args.emplace_back(argv[i]);
    after = after || argv[i] == command.get_name();
  }
  const std::string unknown = drape::unknownOptionMessage(command, args);
  if (unknown.empty()) return e.what();
  return fmt::format("{}: {} ({} --help)", command.get_name(), unknown,
                     chosen.empty() ? "drape" : "drape " + command.get_name());
}

// CLI11 says "--frames: At Most 1 required but received 2" for an option given twice.
std::string usageMessage(const CLI::ParseError& e) {
  const std::string text = e.what();
  const std::size_t at = text.find(": At Most 1 required but received ");
  return at == std::string::npos ? text : text.substr(0, at) + ": given more than once";
}

// A data directory as --version shows it: a missing one (a partial install, a wrong $DRAPE_GLSL_DIR) said so.
std::string shownDir(const std::filesystem::path& dir) {
  std::error_code error;
  return dir.string() + (std::filesystem::is_directory(dir, error) ? "" : " (missing)");
}

// Where the data comes from is part of the answer: it tells an installed drape from a build tree's.
std::string versionText() {
  return fmt::format("drape {}\nglsl      {}\ntextures  {}\nscenes    {}", DRAPE_VERSION,
                     shownDir(drape::dataDir("glsl", "DRAPE_GLSL_DIR")),
                     shownDir(drape::dataDir("textures", "DRAPE_TEXTURE_DIR")), shownDir(drape::dataDir("scenes")));
}

}  // namespace

int main(int argc, char** argv) {
  drape::recordStagesOfFailedAllocations();
  CLI::App app{"Drape: real-time mass-spring cloth simulation on the GPU (OpenGL compute)"};
  app.name("drape");  // --help without arguments comes before parse(), which would name it from argv[0]
  app.require_subcommand(1);
  // Every option's default in its --help (before the subcommands: they take the app's option defaults).
  app.option_defaults()->always_capture_default();
  app.set_version_flag("--version", versionText,
                       "Print the version and where the shaders, textures and scenes are read");
  drape::addSimulateCommand(app);
  drape::addViewCommand(app);
  drape::addRenderCommand(app);
  drape::addBenchCommand(app);
  drape::addAccuracyCommand(app);
  drape::addStabilityCommand(app);
  drape::addPenetrationCommand(app);
  // After the subcommands, which would otherwise inherit it.
  app.footer(
      "drape -f SCENE [view options] opens the viewer on SCENE, as CS184's `clothsim -f SCENE` does "
      "(the same as drape view SCENE).");
  // Nothing asked: the help, as most command lines answer, and no error.
  if (argc == 1) {
    fmt::print("{}", app.help());
    return drape::kExitOk;
  }
  // CS184's viewer opens a scene with `clothsim -f scene.json [-a N -o N]`: the same words open this one.
  std::vector<const char*> args(argv, argv + argc);
  if (args[1] == std::string_view("-f")) {
    if (argc == 2) {
      fmt::print(stderr, "drape: -f: a scene file is required (drape -f SCENE)\n");
      return drape::kExitBadInput;
    }
    args[1] = "view";
  }
  try {
    app.parse(argc, args.data());
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" that exit 0; usage errors are bad input: status 2, one line.
    if (e.get_exit_code() == 0) return app.exit(e);
    const bool no_command = app.get_subcommands().empty() && e.get_name() == "RequiredError";
    const std::string message = no_command ? missingCommandMessage(app, argc, args.data())
                                : dynamic_cast<const CLI::ExtrasError*>(&e) ? extrasMessage(app, e, argc, args.data())
                                                                            : usageMessage(e);
    fmt::print(stderr, "drape: {}\n", message);
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
  } catch (const std::bad_alloc&) {
    const std::string stage = drape::failedAllocationStage(), limit = drape::addressSpaceLimit();
    fmt::print(stderr, "drape: out of memory{}{}\n", stage.empty() ? "" : " while " + stage,
               limit.empty() ? "" : " (this process may use " + limit + ": ulimit -v)");
    return drape::kExitFailure;
  } catch (const std::exception& e) {
    fmt::print(stderr, "drape: error: {}\n", e.what());
    return drape::kExitFailure;
  }
  return 0;
}
