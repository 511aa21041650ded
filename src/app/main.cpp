#include "app/commands.hpp"
#include "core/atomic_file.hpp"
#include "core/data_dir.hpp"
#include "core/scene.hpp"

#include <fmt/core.h>

#include <cstdio>
#include <exception>
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
// that is not a command, and list the commands.
std::string missingCommandMessage(const CLI::App& app, int argc, const char* const* argv) {
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

// Where the data comes from is part of the answer: it tells an installed drape from a build tree's.
std::string versionText() {
  return fmt::format("drape {}\nglsl      {}\ntextures  {}\nscenes    {}", DRAPE_VERSION,
                     drape::dataDir("glsl", "DRAPE_GLSL_DIR").string(),
                     drape::dataDir("textures", "DRAPE_TEXTURE_DIR").string(), drape::dataDir("scenes").string());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Drape: real-time mass-spring cloth simulation on the GPU (OpenGL compute)"};
  app.name("drape");  // --help without arguments comes before parse(), which would name it from argv[0]
  app.require_subcommand(1);
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
    fmt::print(stderr, "drape: {}\n", no_command ? missingCommandMessage(app, argc, args.data()) : usageMessage(e));
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
