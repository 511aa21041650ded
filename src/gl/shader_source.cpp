#include "gl/shader_source.hpp"

#include "core/data_dir.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace drape::gl {
namespace {

std::string trimLeft(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t");
  return begin == std::string::npos ? std::string() : s.substr(begin);
}

// The directive name of a preprocessor line ("include" for `  #  include "x"`) and what follows it.
std::optional<std::pair<std::string, std::string>> splitDirective(const std::string& line) {
  const std::string trimmed = trimLeft(line);
  if (trimmed.empty() || trimmed[0] != '#') return std::nullopt;
  const std::string rest = trimLeft(trimmed.substr(1));
  std::size_t end = 0;
  while (end < rest.size() && (std::isalnum(static_cast<unsigned char>(rest[end])) || rest[end] == '_'))
    ++end;
  return std::make_pair(rest.substr(0, end), trimLeft(rest.substr(end)));
}

bool isIdentifier(const std::string& name) {
  static const std::regex identifier("[A-Za-z_][A-Za-z0-9_]*");
  return std::regex_match(name, identifier);
}

std::string locationPrefix(const std::string& file, int line) {
  return file + ":" + std::to_string(line) + ": ";
}

class Preprocessor {
 public:
  explicit Preprocessor(fs::path root) : root_(std::move(root)) {}

  ShaderSource run(const fs::path& file, const Defines& defines) {
    out_.files.push_back("<preamble>");
    out_.paths.emplace_back();
    out_.text = "#version 450 core\n";
    for (const auto& [name, value] : defines) {
      if (!isIdentifier(name)) throw ShaderError("<defines>: '" + name + "' is not a valid macro name");
      if (value.find('\n') != std::string::npos)
        throw ShaderError("<defines>: the value of " + name + " contains a line break");
      out_.text += "#define " + name + (value.empty() ? "" : " " + value) + "\n";
    }
    std::error_code error;
    const fs::path top = fs::weakly_canonical(file, error);
    if (error || !fs::is_regular_file(top))
      throw ShaderError(displayName(file) + ": shader file not found", displayName(file));
    emitFile(top);
    return std::move(out_);
  }

 private:
  int numberOf(const fs::path& file) {
    const auto [it, inserted] = numbers_.emplace(file, static_cast<int>(out_.files.size()));
    if (inserted) {
      out_.files.push_back(displayName(file));
      out_.paths.push_back(file);
    }
    return it->second;
  }

  // Where `#include "name"` in `including` refers to: next to the including file, then under root.
  std::optional<fs::path> resolve(const fs::path& including, const std::string& name) const {
    for (const fs::path& base : {including.parent_path(), root_}) {
      std::error_code error;
      const fs::path candidate = fs::weakly_canonical(base / name, error);
      if (!error && fs::is_regular_file(candidate)) return candidate;
    }
    return std::nullopt;
  }

  void emitFile(const fs::path& file) {
    const int number = numberOf(file);
    const std::string name = out_.files[number];
    std::ifstream in(file, std::ios::binary);
    if (!in) throw ShaderError(name + ": cannot read the file", name);
    stack_.push_back(file);

    out_.text += "#line 1 " + std::to_string(number) + "\n";
    std::string line;
    int line_number = 0;
    while (std::getline(in, line)) {
      ++line_number;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      const auto directive = splitDirective(line);
      if (!directive) {
        out_.text += line + "\n";
        continue;
      }
      const auto& [word, argument] = *directive;
      if (word == "version") {
        throw ShaderError(locationPrefix(name, line_number) +
                              "shader files carry no #version; the loader prepends '#version 450 core'",
                          name, line_number);
      } else if (word == "pragma" && argument.rfind("once", 0) == 0) {
        once_.insert(file);
        out_.text += "\n";  // keeps the line count, so no #line is needed
      } else if (word == "include") {
        emitInclude(file, name, line_number, argument);
        out_.text += "#line " + std::to_string(line_number + 1) + " " + std::to_string(number) + "\n";
      } else {
        out_.text += line + "\n";
      }
    }
    stack_.pop_back();
  }

  void emitInclude(const fs::path& file, const std::string& name, int line_number, const std::string& argument) {
    const std::string where = locationPrefix(name, line_number);
    const auto close = argument.find('"', 1);
    if (argument.empty() || argument[0] != '"' || close == std::string::npos)
      throw ShaderError(where + "expected #include \"file\"", name, line_number);
    const std::string target = argument.substr(1, close - 1);
    const auto resolved = resolve(file, target);
    if (!resolved)
      throw ShaderError(
          where + "cannot find include \"" + target + "\" (looked next to the file and in " + displayName(root_) + ")",
          name, line_number);
    if (once_.count(*resolved)) return;
    if (std::find(stack_.begin(), stack_.end(), *resolved) != stack_.end()) {
      std::string chain;
      for (const fs::path& p : stack_)
        chain += displayName(p) + " -> ";
      throw ShaderError(where + "include cycle: " + chain + displayName(*resolved), name, line_number);
    }
    emitFile(*resolved);
  }

  fs::path root_;
  ShaderSource out_;
  std::vector<fs::path> stack_;  // files being included, outermost first
  std::set<fs::path> once_;      // files that said #pragma once
  std::map<fs::path, int> numbers_;
};

struct TranslatedLine {
  std::string text;
  std::string file;  // empty when the line had no known location format
  int line = 0;
};

TranslatedLine translateLine(const ShaderSource& source, const std::string& line) {
  // Mesa: "0:12(3): error: ..."; NVIDIA: "0(12) : error C0000: ..."; glslang and others: "ERROR: 0:12: ...".
  static const std::regex mesa(R"(^(\d+):(\d+)\((\d+)\):\s?(.*)$)");
  static const std::regex nvidia(R"(^(\d+)\((\d+)\)\s*:\s?(.*)$)");
  static const std::regex glslang(R"(^(ERROR|WARNING|INFO):\s*(\d+):(\d+):\s?(.*)$)");
  const auto fileOf = [&](const std::string& number) -> std::optional<std::string> {
    const unsigned long index = std::stoul(number);
    if (index >= source.files.size()) return std::nullopt;
    return source.files[index];
  };
  std::smatch m;
  if (std::regex_match(line, m, mesa)) {
    if (const auto file = fileOf(m[1])) {
      const int n = std::stoi(m[2]);
      return {*file + ":" + m[2].str() + ":" + m[3].str() + ": " + m[4].str(), *file, n};
    }
  } else if (std::regex_match(line, m, nvidia)) {
    if (const auto file = fileOf(m[1])) return {*file + ":" + m[2].str() + ": " + m[3].str(), *file, std::stoi(m[2])};
  } else if (std::regex_match(line, m, glslang)) {
    if (const auto file = fileOf(m[2]))
      return {*file + ":" + m[3].str() + ": " + m[1].str() + ": " + m[4].str(), *file, std::stoi(m[3])};
  }
  return {line, {}, 0};
}

}  // namespace

std::string ShaderSource::translateLog(const std::string& log) const {
  std::istringstream in(log);
  std::string line;
  std::string out;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    out += translateLine(*this, line).text + "\n";
  }
  return out;
}

std::pair<std::string, int> ShaderSource::firstLocation(const std::string& log) const {
  std::istringstream in(log);
  std::string line;
  while (std::getline(in, line)) {
    const TranslatedLine translated = translateLine(*this, line);
    if (!translated.file.empty()) return {translated.file, translated.line};
  }
  return {};
}

ShaderSource preprocess(const fs::path& file, const Defines& defines, const fs::path& root) {
  return Preprocessor(root).run(file, defines);
}

fs::path glslRoot() {
  return dataDir("glsl", "DRAPE_GLSL_DIR");
}

std::string displayName(const fs::path& file) {
#ifdef DRAPE_SOURCE_DIR
  std::error_code error;
  const fs::path source_dir = fs::weakly_canonical(DRAPE_SOURCE_DIR, error);
  const fs::path canonical = fs::weakly_canonical(file, error);
  if (!error) {
    const fs::path relative = canonical.lexically_relative(source_dir);
    if (!relative.empty() && *relative.begin() != "..") return relative.generic_string();
  }
#endif
  return file.generic_string();
}

}  // namespace drape::gl
