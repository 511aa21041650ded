// GLSL source assembly without any GL call (also built into the host tool drape_glsl_preprocess that
// checks every shader at build time): #version, variant #defines, #include, #line mapping.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace drape::gl {

// A shader that cannot be assembled, compiled or linked. what() is "file:line: message" (one such
// line per compiler message); file()/line() give the first location, empty/0 when there is none.
class ShaderError : public std::runtime_error {
 public:
  explicit ShaderError(const std::string& message, std::string file = {}, int line = 0)
      : std::runtime_error(message), file_(std::move(file)), line_(line) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }

 private:
  std::string file_;
  int line_ = 0;
};

using Defines = std::vector<std::pair<std::string, std::string>>;

// Preprocessed text ready for glShaderSource. Every file it came from has a GLSL source-string
// number (its index in `files`) used in the `#line N F` directives, so compiler messages can be
// mapped back. Index 0 is the preamble (#version and #defines); the shader's own file is 1.
struct ShaderSource {
  std::string text;
  std::vector<std::string> files;            // source-string number -> display name ("glsl/sim/forces_integrate.comp")
  std::vector<std::filesystem::path> paths;  // source-string number -> canonical path (empty for the preamble)

  // Rewrites compiler/validator messages from source-string numbers to file names:
  //   Mesa     "0:12(3): error: ..."          -> "glsl/x.comp:12:3: error: ..."
  //   NVIDIA   "0(12) : error C0000: ..."     -> "glsl/x.comp:12: error C0000: ..."
  //   glslang  "ERROR: 0:12: '...' : ..."     -> "glsl/x.comp:12: ERROR: '...' : ..."
  // Lines in no known format are kept as they are.
  std::string translateLog(const std::string& log) const;

  // First "file:line" found in a compiler log (translated), or {"", 0}.
  std::pair<std::string, int> firstLocation(const std::string& log) const;
};

// Reads `file` and produces: "#version 450 core", one "#define NAME VALUE" per define (in order),
// then the file with every `#include "x"` replaced by x's text, recursively. An include is looked
// up relative to the including file, then relative to `root`. A file containing `#pragma once` is
// included once per shader; classic #ifndef guards work as usual since the text stays GLSL.
// Includes are resolved textually, also inside #if blocks (the text stays inside the block).
// Shader files carry no #version. Throws ShaderError "file:line: ..." on a missing include, an
// include cycle, a #version line, an unreadable file or a malformed define name.
ShaderSource preprocess(const std::filesystem::path& file, const Defines& defines, const std::filesystem::path& root);

// The glsl/ directory: $DRAPE_GLSL_DIR when set, else the installed or the source tree's (core/data_dir.hpp).
std::filesystem::path glslRoot();

// How a file is named in messages: relative to the source tree when inside it, else as given.
std::string displayName(const std::filesystem::path& file);

}  // namespace drape::gl
