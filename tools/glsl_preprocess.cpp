// drape_glsl_preprocess: the shader loader's preprocessing (version, defines, includes, #line) as a
// host tool, so every shader variant is checked by glslangValidator at build time, with compiler
// messages mapped back to file and line exactly as at run time.
//
//   drape_glsl_preprocess [--root DIR] [-D NAME[=VALUE]]... FILE
//       prints the preprocessed text
//   drape_glsl_preprocess [--root DIR] [-D NAME[=VALUE]]... --check VALIDATOR --out TEXT
//                         [--stamp STAMP --depfile DEP] FILE
//       writes the text to TEXT, runs `VALIDATOR -S <stage> TEXT`, prints its messages as
//       file:line, fails when it fails; on success touches STAMP and writes DEP (every file read).
#include "gl/shader_source.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>

namespace fs = std::filesystem;
using drape::gl::Defines;
using drape::gl::ShaderError;
using drape::gl::ShaderSource;

namespace {

struct Options {
  fs::path file, root, out, stamp, depfile;
  std::string validator;
  Defines defines;
};

std::string shellQuoted(const fs::path& path) {
  std::string text = "'";
  for (char c : path.string())
    text += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return text + "'";
}

std::string stageOf(const fs::path& file) {
  const std::string ext = file.extension().string();
  for (const char* stage : {"comp", "vert", "frag", "geom", "tesc", "tese"})
    if (ext == std::string(".") + stage) return stage;
  throw ShaderError(drape::gl::displayName(file) + ": cannot tell the shader stage from the extension '" + ext + "'");
}

Options parse(int argc, char** argv) {
  Options options;
  options.root = drape::gl::glslRoot();
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--root") {
      options.root = value();
    } else if (arg == "-D") {
      const std::string define = value();
      const auto equals = define.find('=');
      options.defines.emplace_back(define.substr(0, equals),
                                   equals == std::string::npos ? std::string() : define.substr(equals + 1));
    } else if (arg == "--check") {
      options.validator = value();
    } else if (arg == "--out") {
      options.out = value();
    } else if (arg == "--stamp") {
      options.stamp = value();
    } else if (arg == "--depfile") {
      options.depfile = value();
    } else if (!arg.empty() && arg[0] == '-') {
      throw std::invalid_argument("unknown option " + arg);
    } else if (options.file.empty()) {
      options.file = arg;
    } else {
      throw std::invalid_argument("more than one shader file: " + arg);
    }
  }
  if (options.file.empty()) throw std::invalid_argument("no shader file given");
  if (!options.validator.empty() && options.out.empty()) throw std::invalid_argument("--check needs --out");
  return options;
}

std::string variantName(const Defines& defines) {
  std::string name;
  for (const auto& [key, value] : defines)
    name += " " + key + (value.empty() ? "" : "=" + value);
  return name.empty() ? " (no defines)" : name;
}

// Runs the validator on the written text; returns its translated messages and whether it passed.
bool validate(const Options& options, const ShaderSource& source, std::string& messages) {
  const fs::path log = fs::path(options.out).concat(".log");
  const std::string command = shellQuoted(options.validator) + " -S " + stageOf(options.file) + " " +
                              shellQuoted(options.out) + " > " + shellQuoted(log) + " 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  std::string relevant;
  std::string line;
  // glslang echoes the file name and a summary line; keep only the messages with a location.
  for (std::istringstream lines(source.translateLog(text.str())); std::getline(lines, line);) {
    if (line.find(": ERROR: ") != std::string::npos || line.find(": WARNING: ") != std::string::npos)
      relevant += line + "\n";
  }
  messages = relevant.empty() ? text.str() : relevant;
  return status == 0;
}

void writeDepfile(const Options& options, const ShaderSource& source) {
  std::ofstream dep(options.depfile);
  const auto escaped = [](const fs::path& path) {
    std::string text;
    for (char c : path.string())
      text += c == ' ' ? std::string("\\ ") : std::string(1, c);
    return text;
  };
  dep << escaped(options.stamp) << ":";
  for (const fs::path& path : source.paths)
    if (!path.empty()) dep << " " << escaped(path);
  dep << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  try {
    options = parse(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "drape_glsl_preprocess: " << e.what() << "\n";
    return 2;
  }
  try {
    const ShaderSource source = drape::gl::preprocess(options.file, options.defines, options.root);
    if (options.validator.empty()) {
      if (options.out.empty()) {
        std::cout << source.text;
      } else {
        std::ofstream(options.out) << source.text;
      }
      return 0;
    }
    std::ofstream(options.out) << source.text;
    std::string messages;
    if (!validate(options, source, messages)) {
      std::cerr << messages << drape::gl::displayName(options.file) << ": failed the offline check with"
                << variantName(options.defines) << "\n";
      return 1;
    }
    if (!options.depfile.empty()) writeDepfile(options, source);
    if (!options.stamp.empty()) std::ofstream(options.stamp) << variantName(options.defines) << "\n";
    return 0;
  } catch (const ShaderError& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }
}
