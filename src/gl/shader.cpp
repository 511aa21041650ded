#include "gl/shader.hpp"

#include <algorithm>
#include <optional>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

namespace drape::gl {
namespace {

fs::path resolveShader(const fs::path& file) {
  return file.is_absolute() ? file : glslRoot() / file;
}

std::string trimTrailing(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ' || text.back() == '\0'))
    text.pop_back();
  return text;
}

const char* stageName(GLenum stage) {
  switch (stage) {
    case GL_COMPUTE_SHADER:
      return "compute";
    case GL_VERTEX_SHADER:
      return "vertex";
    case GL_FRAGMENT_SHADER:
      return "fragment";
    case GL_GEOMETRY_SHADER:
      return "geometry";
    default:
      return "shader";
  }
}

// Compiles `text` into `shader`. On failure deletes the shader and returns its info log.
std::optional<std::string> compile(GLuint shader, const std::string& text) {
  const char* source = text.c_str();
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint compiled = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &compiled);
  if (compiled) return std::nullopt;
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  glGetShaderInfoLog(shader, length, nullptr, log.data());
  glDeleteShader(shader);
  return log;
}

// Compiles one stage and attaches it; the shader is flagged for deletion and goes with the program.
void attachStage(GLuint program, GLenum stage, const fs::path& file, const Defines& defines) {
  const ShaderSource source = preprocess(resolveShader(file), defines, glslRoot());
  const GLuint shader = glCreateShader(stage);
  if (const std::optional<std::string> log = compile(shader, source.text)) {
    const auto [where, line] = source.firstLocation(*log);
    std::string message = trimTrailing(source.translateLog(trimTrailing(*log)));
    // A log with no location still names the shader.
    if (where.empty()) message = source.files.at(1) + ": " + stageName(stage) + " shader failed to compile: " + message;
    throw ShaderError(message, where.empty() ? source.files.at(1) : where, line);
  }
  glAttachShader(program, shader);
  glDeleteShader(shader);
}

Program link(std::vector<std::pair<GLenum, fs::path>> stages, const Defines& defines) {
  std::string label;
  for (const auto& [stage, file] : stages)
    label += (label.empty() ? "" : "+") + displayName(resolveShader(file));
  // Owned from the start, so a compile error in a later stage frees what was made before it.
  UniqueName<ProgramDeleter> program(glCreateProgram());
  for (const auto& [stage, file] : stages)
    attachStage(program.get(), stage, file, defines);
  glLinkProgram(program.get());
  GLint linked = GL_FALSE;
  glGetProgramiv(program.get(), GL_LINK_STATUS, &linked);
  if (!linked) {
    GLint length = 0;
    glGetProgramiv(program.get(), GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program.get(), length, nullptr, log.data());
    throw ShaderError(label + ": link failed: " + trimTrailing(log), label);
  }
  checkDebugErrors();
  return Program(program.release(), label);
}

// Same as attachStage, for text that is not in a file (no includes, no #line mapping needed).
void attachText(GLuint program, GLenum stage, const std::string& text, const std::string& label,
                const Defines& defines) {
  std::string full = "#version 450 core\n";
  for (const auto& [name, value] : defines)
    full += "#define " + name + " " + value + "\n";
  full += "#line 1 1\n" + text;
  const GLuint shader = glCreateShader(stage);
  if (const std::optional<std::string> log = compile(shader, full)) {
    throw ShaderError(label + ": " + stageName(stage) + " shader failed to compile: " + trimTrailing(*log), label);
  }
  glAttachShader(program, shader);
  glDeleteShader(shader);
}

}  // namespace

Program compileComputeText(const std::string& text, const std::string& label, const Defines& defines) {
  UniqueName<ProgramDeleter> program(glCreateProgram());
  attachText(program.get(), GL_COMPUTE_SHADER, text, label, defines);
  glLinkProgram(program.get());
  GLint linked = GL_FALSE;
  glGetProgramiv(program.get(), GL_LINK_STATUS, &linked);
  if (!linked) throw ShaderError(label + ": link failed", label);
  checkDebugErrors();
  return Program(program.release(), label);
}

bool timerQueriesWork() {
  static std::optional<bool> works;
  if (works) return *works;
  // A compute dispatch, because that is what the solver times. llvmpipe answers every
  // GL_TIME_ELAPSED query with a token 1 ns, so "positive" is not enough: this dispatch takes well
  // over a microsecond on any GPU (launch cost alone), and a few milliseconds on llvmpipe.
  const Program program = compileComputeText(
      "layout(local_size_x = 64) in;\n"
      "layout(std430, binding = 0) buffer Scratch { float values[]; };\n"
      "void main() {\n"
      "  uint i = gl_GlobalInvocationID.x;\n"
      "  float x = values[i];\n"
      "  for (int k = 0; k < 64; ++k) x = sqrt(x * x + float(k));\n"
      "  values[i] = x;\n"
      "}\n",
      "timer-query probe");
  const std::uint32_t count = 1u << 14;
  const Buffer scratch = Buffer::create(count * sizeof(float), nullptr, 0);
  GLint previous = 0;
  glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, 0, &previous);
  scratch.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
  const Query query = Query::create(GL_TIME_ELAPSED);
  query.begin();
  program.dispatch(program.groupsFor(count));
  query.end();
  constexpr std::uint64_t kMinimumNs = 1000;
  works = query.result() >= kMinimumNs;
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLuint>(previous));
  glUseProgram(0);
  return *works;
}

Program compileCompute(const fs::path& file, const Defines& defines) {
  return link({{GL_COMPUTE_SHADER, file}}, defines);
}

Program compileGraphics(const fs::path& vert, const fs::path& frag, const Defines& defines, const fs::path& geom) {
  std::vector<std::pair<GLenum, fs::path>> stages = {{GL_VERTEX_SHADER, vert}, {GL_FRAGMENT_SHADER, frag}};
  if (!geom.empty()) stages.emplace_back(GL_GEOMETRY_SHADER, geom);
  return link(std::move(stages), defines);
}

}  // namespace drape::gl
