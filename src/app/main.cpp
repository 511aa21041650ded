#include "app/commands.hpp"
#include "core/scene.hpp"

#include <fmt/core.h>

#include <cstdio>
#include <exception>

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
    fmt::print(stderr, "drape: {}\n", e.what());
    return drape::kExitBadInput;
  } catch (const drape::CommandError& e) {
    fmt::print(stderr, "drape: {}\n", e.what());
    return e.status();
  } catch (const drape::SceneError& e) {
    fmt::print(stderr, "drape: {}\n", e.what());
    return drape::kExitBadInput;
  } catch (const std::exception& e) {
    fmt::print(stderr, "drape: error: {}\n", e.what());
    return drape::kExitFailure;
  }
  return 0;
}
