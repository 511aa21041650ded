#include "gl/objects.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cstring>
#include <optional>

namespace drape::gl {

namespace {
thread_local DispatchRecorder* t_dispatch_recorder = nullptr;
thread_local SyncCounts t_sync_counts;
}  // namespace

// The one place a wait is counted and recorded.
struct WaitRecording {
  static void record(long long SyncCounts::*counter, const char* what) {
    ++(t_sync_counts.*counter);
    if (t_dispatch_recorder) t_dispatch_recorder->waits_.push_back({what});
  }
};

namespace {

void checkRange(const char* what, std::size_t offset, std::size_t bytes, std::size_t size) {
  if (offset > size || bytes > size - offset) {
    throw std::out_of_range(std::string("Buffer::") + what + ": bytes [" + std::to_string(offset) + ", " +
                            std::to_string(offset + bytes) + ") outside a buffer of " + std::to_string(size) +
                            " bytes");
  }
}

std::string glslTypeName(GLenum type) {
  switch (type) {
    case GL_INT:
      return "int";
    case GL_UNSIGNED_INT:
      return "uint";
    case GL_FLOAT:
      return "float";
    case GL_BOOL:
      return "bool";
    case GL_FLOAT_VEC2:
      return "vec2";
    case GL_FLOAT_VEC3:
      return "vec3";
    case GL_FLOAT_VEC4:
      return "vec4";
    case GL_INT_VEC3:
      return "ivec3";
    case GL_FLOAT_MAT3:
      return "mat3";
    case GL_FLOAT_MAT4:
      return "mat4";
    default:
      return "GL type " + std::to_string(type);
  }
}

// Samplers and images are set through glProgramUniform1i with the texture/image unit.
bool isSamplerOrImage(GLenum type) {
  switch (type) {
    case GL_SAMPLER_2D:
    case GL_SAMPLER_3D:
    case GL_SAMPLER_CUBE:
    case GL_SAMPLER_2D_SHADOW:
    case GL_SAMPLER_2D_ARRAY:
    case GL_SAMPLER_2D_MULTISAMPLE:
    case GL_SAMPLER_CUBE_SHADOW:
    case GL_SAMPLER_BUFFER:
    case GL_INT_SAMPLER_2D:
    case GL_UNSIGNED_INT_SAMPLER_2D:
    case GL_IMAGE_2D:
    case GL_IMAGE_3D:
    case GL_IMAGE_CUBE:
    case GL_INT_IMAGE_2D:
    case GL_UNSIGNED_INT_IMAGE_2D:
      return true;
    default:
      return false;
  }
}

}  // namespace

// ---- Buffer

Buffer Buffer::create(std::size_t bytes, const void* data, GLbitfield flags) {
  Buffer buffer;
  GLuint id = 0;
  glCreateBuffers(1, &id);
  buffer.name_ = UniqueName<BufferDeleter>(id);
  buffer.size_ = bytes;
  // glNamedBufferStorage rejects size 0, yet an empty set (no pins, no spheres) is legitimate.
  const std::size_t storage = std::max<std::size_t>(bytes, 16);
  glNamedBufferStorage(id, static_cast<GLsizeiptr>(storage), bytes == 0 ? nullptr : data, flags);
  checkDebugErrors();
  return buffer;
}

void Buffer::upload(std::size_t offset, std::size_t bytes, const void* data) {
  checkRange("upload", offset, bytes, size_);
  if (bytes == 0) return;
  glNamedBufferSubData(id(), static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), data);
  checkDebugErrors();
}

void Buffer::downloadBytes(std::size_t offset, std::size_t bytes, void* out) const {
  checkRange("download", offset, bytes, size_);
  if (bytes == 0) return;
  WaitRecording::record(&SyncCounts::readbacks, "download");
  glGetNamedBufferSubData(id(), static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), out);
  checkDebugErrors();
}

Buffer Buffer::createReadMapped(std::size_t bytes) {
  constexpr GLbitfield kFlags = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
  Buffer buffer = create(bytes, nullptr, kFlags);
  buffer.mapped_ = glMapNamedBufferRange(buffer.id(), 0, GLsizeiptr(std::max<std::size_t>(bytes, 1)), kFlags);
  checkDebugErrors();
  if (buffer.mapped_ == nullptr) throw GlError("glMapNamedBufferRange of a persistent read buffer failed");
  return buffer;
}

void Buffer::bindBase(GLenum target, GLuint index) const {
  glBindBufferBase(target, index, id());
  checkDebugErrors();
}

void Buffer::clear() {
  // A null data pointer fills with zeros.
  glClearNamedBufferData(id(), GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, nullptr);
  checkDebugErrors();
}

void Buffer::copyTo(Buffer& target, std::size_t source_offset, std::size_t target_offset, std::size_t bytes) const {
  checkRange("copyTo (source)", source_offset, bytes, size_);
  checkRange("copyTo (target)", target_offset, bytes, target.size_);
  if (bytes == 0) return;
  glCopyNamedBufferSubData(id(), target.id(), static_cast<GLintptr>(source_offset),
                           static_cast<GLintptr>(target_offset), static_cast<GLsizeiptr>(bytes));
  checkDebugErrors();
}

// ---- Program

Program::Program(GLuint linked_program, std::string label) : name_(linked_program), label_(std::move(label)) {
  // Shaders stay attached (flagged for deletion) until the program goes, so the stages are known here;
  // querying GL_COMPUTE_WORK_GROUP_SIZE on a graphics program would be a GL error.
  GLint attached = 0;
  glGetProgramiv(id(), GL_ATTACHED_SHADERS, &attached);
  std::vector<GLuint> shaders(static_cast<std::size_t>(attached));
  if (attached > 0) glGetAttachedShaders(id(), attached, nullptr, shaders.data());
  for (GLuint shader : shaders) {
    GLint type = 0;
    glGetShaderiv(shader, GL_SHADER_TYPE, &type);
    if (type == GL_COMPUTE_SHADER) compute_ = true;
  }
  if (compute_) {
    GLint size[3] = {0, 0, 0};
    glGetProgramiv(id(), GL_COMPUTE_WORK_GROUP_SIZE, size);
    local_size_ = glm::uvec3(size[0], size[1], size[2]);
  }

  GLint count = 0, max_length = 0;
  glGetProgramiv(id(), GL_ACTIVE_UNIFORMS, &count);
  glGetProgramiv(id(), GL_ACTIVE_UNIFORM_MAX_LENGTH, &max_length);
  std::vector<GLchar> buffer(static_cast<std::size_t>(std::max(max_length, 1)));
  for (GLint i = 0; i < count; ++i) {
    GLsizei length = 0;
    GLint array_size = 0;
    GLenum type = 0;
    glGetActiveUniform(id(), static_cast<GLuint>(i), max_length, &length, &array_size, &type, buffer.data());
    std::string name(buffer.data(), static_cast<std::size_t>(length));
    const GLint location = glGetUniformLocation(id(), name.c_str());
    if (location < 0) continue;  // a member of a uniform block, set through its buffer
    uniforms_[name] = {location, type, array_size};
    // Arrays are reported as "name[0]"; their first element is also reachable as "name".
    if (name.size() > 3 && name.compare(name.size() - 3, 3, "[0]") == 0)
      uniforms_[name.substr(0, name.size() - 3)] = {location, type, array_size};
  }
  checkDebugErrors();
}

bool Program::hasUniform(const char* name) const {
  return uniforms_.count(name) != 0;
}

GLint Program::locate(const char* name, GLenum type) const {
  const auto it = uniforms_.find(name);
  if (it == uniforms_.end())
    throw GlError("program " + label_ + " has no active uniform '" + name + "' (misspelt, or removed by a #define?)");
  const GLenum actual = it->second.type;
  const bool matches = actual == type || (type == GL_INT && isSamplerOrImage(actual));
  if (!matches) {
    throw GlError("uniform '" + std::string(name) + "' of program " + label_ + " is " + glslTypeName(actual) +
                  ", set as " + glslTypeName(type));
  }
  return it->second.location;
}

void Program::use() const {
  glUseProgram(id());
  checkDebugErrors();
}

SyncCounts syncCounts() {
  return t_sync_counts;
}

void finish() {
  WaitRecording::record(&SyncCounts::finishes, "finish");
  glFinish();
}

DispatchRecorder::DispatchRecorder() : outer_(t_dispatch_recorder) {
  t_dispatch_recorder = this;
}

DispatchRecorder::~DispatchRecorder() {
  t_dispatch_recorder = outer_;
}

void Program::dispatch(glm::uvec3 groups) const {
  glUseProgram(id());
  glDispatchCompute(groups.x, groups.y, groups.z);
  checkDebugErrors();
  if (t_dispatch_recorder) t_dispatch_recorder->dispatches_.push_back({label_, groups});
}

void Program::dispatchIndirect(std::size_t offset) const {
  glUseProgram(id());
  glDispatchComputeIndirect(GLintptr(offset));
  checkDebugErrors();
  if (t_dispatch_recorder) t_dispatch_recorder->dispatches_.push_back({label_, glm::uvec3(0), true});
}

glm::uvec3 Program::localSize() const {
  if (!compute_) throw GlError("program " + label_ + " is not a compute program: it has no local size");
  return local_size_;
}

glm::uvec3 Program::groupsFor(std::uint32_t invocations) const {
  const std::uint32_t local = localSize().x;
  return {(invocations + local - 1) / local, 1u, 1u};
}

void Program::setUniform(const char* name, int value) const {
  glProgramUniform1i(id(), locate(name, GL_INT), value);
  checkDebugErrors();
}
void Program::setUniform(const char* name, unsigned value) const {
  glProgramUniform1ui(id(), locate(name, GL_UNSIGNED_INT), value);
  checkDebugErrors();
}
void Program::setUniform(const char* name, float value) const {
  glProgramUniform1f(id(), locate(name, GL_FLOAT), value);
  checkDebugErrors();
}
void Program::setUniform(const char* name, double value) const {
  glProgramUniform1d(id(), locate(name, GL_DOUBLE), value);
  checkDebugErrors();
}
void Program::setUniform(const char* name, bool value) const {
  glProgramUniform1i(id(), locate(name, GL_BOOL), value ? 1 : 0);
  checkDebugErrors();
}
void Program::setUniform(const char* name, const glm::vec2& value) const {
  glProgramUniform2fv(id(), locate(name, GL_FLOAT_VEC2), 1, glm::value_ptr(value));
  checkDebugErrors();
}
void Program::setUniform(const char* name, const glm::vec3& value) const {
  glProgramUniform3fv(id(), locate(name, GL_FLOAT_VEC3), 1, glm::value_ptr(value));
  checkDebugErrors();
}
void Program::setUniform(const char* name, const glm::vec4& value) const {
  glProgramUniform4fv(id(), locate(name, GL_FLOAT_VEC4), 1, glm::value_ptr(value));
  checkDebugErrors();
}
void Program::setUniform(const char* name, const glm::ivec3& value) const {
  glProgramUniform3iv(id(), locate(name, GL_INT_VEC3), 1, glm::value_ptr(value));
  checkDebugErrors();
}
void Program::setUniform(const char* name, const glm::uvec2& value) const {
  glProgramUniform2uiv(id(), locate(name, GL_UNSIGNED_INT_VEC2), 1, glm::value_ptr(value));
  checkDebugErrors();
}
void Program::setUniform(const char* name, const std::vector<float>& values) const {
  const GLint location = locate(name, GL_FLOAT);
  const GLint size = uniforms_.at(name).size;
  if (GLint(values.size()) > size)
    throw GlError("uniform '" + std::string(name) + "' of program " + label_ + " holds " + std::to_string(size) +
                  " floats, set with " + std::to_string(values.size()));
  glProgramUniform1fv(id(), location, GLsizei(values.size()), values.data());
  checkDebugErrors();
}
void Program::setUniform(const char* name, const glm::mat3& value) const {
  glProgramUniformMatrix3fv(id(), locate(name, GL_FLOAT_MAT3), 1, GL_FALSE, glm::value_ptr(value));
  checkDebugErrors();
}
void Program::setUniform(const char* name, const glm::mat4& value) const {
  glProgramUniformMatrix4fv(id(), locate(name, GL_FLOAT_MAT4), 1, GL_FALSE, glm::value_ptr(value));
  checkDebugErrors();
}

// ---- Texture

Texture Texture::create2D(int width, int height, GLenum internal_format, int levels) {
  Texture texture;
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &id);
  texture.name_ = UniqueName<TextureDeleter>(id);
  texture.target_ = GL_TEXTURE_2D;
  texture.width_ = width;
  texture.height_ = height;
  texture.levels_ = levels;
  glTextureStorage2D(id, levels, internal_format, width, height);
  checkDebugErrors();
  return texture;
}

Texture Texture::create2DMultisample(int width, int height, GLenum internal_format, int samples) {
  Texture texture;
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &id);
  texture.name_ = UniqueName<TextureDeleter>(id);
  texture.target_ = GL_TEXTURE_2D_MULTISAMPLE;
  texture.width_ = width;
  texture.height_ = height;
  texture.levels_ = 1;
  glTextureStorage2DMultisample(id, samples, internal_format, width, height, GL_TRUE);
  checkDebugErrors();
  return texture;
}

Texture Texture::createCube(int size, GLenum internal_format, int levels) {
  Texture texture;
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_CUBE_MAP, 1, &id);
  texture.name_ = UniqueName<TextureDeleter>(id);
  texture.target_ = GL_TEXTURE_CUBE_MAP;
  texture.width_ = size;
  texture.height_ = size;
  texture.levels_ = levels;
  glTextureStorage2D(id, levels, internal_format, size, size);
  checkDebugErrors();
  return texture;
}

int Texture::fullMipLevels(int width, int height) {
  int levels = 1;
  for (int size = std::max(width, height); size > 1; size /= 2)
    ++levels;
  return levels;
}

void Texture::upload2D(GLenum format, GLenum type, const void* pixels, int level) {
  // Callers hand over tightly packed rows (RGB8 rows are not 4-byte aligned in general).
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(id(), level, 0, 0, std::max(width_ >> level, 1), std::max(height_ >> level, 1), format, type,
                      pixels);
  checkDebugErrors();
}

void Texture::uploadCubeFace(int face, GLenum format, GLenum type, const void* pixels, int level) {
  if (target_ != GL_TEXTURE_CUBE_MAP || face < 0 || face > 5)
    throw GlError("Texture::uploadCubeFace: face " + std::to_string(face) + " of a texture that is not a cube map");
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  const int size = std::max(width_ >> level, 1);
  // With direct state access a cube map is addressed as 6 layers, z = face.
  glTextureSubImage3D(id(), level, 0, 0, face, size, size, 1, format, type, pixels);
  checkDebugErrors();
}

void Texture::bind(GLuint unit) const {
  glBindTextureUnit(unit, id());
  checkDebugErrors();
}

void Texture::generateMipmaps() {
  glGenerateTextureMipmap(id());
  checkDebugErrors();
}

void Texture::setSampling(GLenum min_filter, GLenum mag_filter, GLenum wrap) {
  glTextureParameteri(id(), GL_TEXTURE_MIN_FILTER, static_cast<GLint>(min_filter));
  glTextureParameteri(id(), GL_TEXTURE_MAG_FILTER, static_cast<GLint>(mag_filter));
  glTextureParameteri(id(), GL_TEXTURE_WRAP_S, static_cast<GLint>(wrap));
  glTextureParameteri(id(), GL_TEXTURE_WRAP_T, static_cast<GLint>(wrap));
  glTextureParameteri(id(), GL_TEXTURE_WRAP_R, static_cast<GLint>(wrap));
  checkDebugErrors();
}

// ---- Renderbuffer, Framebuffer, VertexArray

Renderbuffer Renderbuffer::create(int width, int height, GLenum internal_format, int samples) {
  Renderbuffer renderbuffer;
  GLuint id = 0;
  glCreateRenderbuffers(1, &id);
  renderbuffer.name_ = UniqueName<RenderbufferDeleter>(id);
  if (samples > 1) {
    glNamedRenderbufferStorageMultisample(id, samples, internal_format, width, height);
  } else {
    glNamedRenderbufferStorage(id, internal_format, width, height);
  }
  checkDebugErrors();
  return renderbuffer;
}

Framebuffer Framebuffer::createColorDepth(int width, int height, int samples) {
  Framebuffer framebuffer;
  framebuffer.width_ = width;
  framebuffer.height_ = height;
  framebuffer.samples_ = std::max(samples, 1);
  if (framebuffer.samples_ > 1) {
    framebuffer.color_ = Texture::create2DMultisample(width, height, GL_RGBA8, framebuffer.samples_);
  } else {
    framebuffer.color_ = Texture::create2D(width, height, GL_RGBA8);
    framebuffer.color_.setSampling(GL_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE);
  }
  framebuffer.depth_ = Renderbuffer::create(width, height, GL_DEPTH_COMPONENT24, framebuffer.samples_);
  GLuint id = 0;
  glCreateFramebuffers(1, &id);
  framebuffer.name_ = UniqueName<FramebufferDeleter>(id);
  glNamedFramebufferTexture(id, GL_COLOR_ATTACHMENT0, framebuffer.color_.id(), 0);
  glNamedFramebufferRenderbuffer(id, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, framebuffer.depth_.id());
  const GLenum status = glCheckNamedFramebufferStatus(id, GL_FRAMEBUFFER);
  checkDebugErrors();
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throw GlError("framebuffer " + std::to_string(width) + "x" + std::to_string(height) + " with " +
                  std::to_string(framebuffer.samples_) + " samples is incomplete (status " + std::to_string(status) +
                  ")");
  }
  return framebuffer;
}

int Framebuffer::maxSamples() {
  GLint renderbuffer = 1, texture = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &renderbuffer);
  glGetIntegerv(GL_MAX_COLOR_TEXTURE_SAMPLES, &texture);
  return std::max(1, std::min(int(renderbuffer), int(texture)));
}

void Framebuffer::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, id());
  glViewport(0, 0, width_, height_);
  checkDebugErrors();
}

void Framebuffer::bindDefault() {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void Framebuffer::blitColorTo(GLuint target_framebuffer, glm::ivec2 target_size) const {
  const bool same_size = target_size == glm::ivec2(width_, height_);
  if (samples_ > 1 && !same_size)
    throw GlError("Framebuffer::blitColorTo: a multisample resolve cannot scale; recreate the framebuffer at " +
                  std::to_string(target_size.x) + "x" + std::to_string(target_size.y));
  glBlitNamedFramebuffer(id(), target_framebuffer, 0, 0, width_, height_, 0, 0, target_size.x, target_size.y,
                         GL_COLOR_BUFFER_BIT, same_size ? GL_NEAREST : GL_LINEAR);
  checkDebugErrors();
}

std::vector<std::uint8_t> Framebuffer::readPixelsRGBA() const {
  if (samples_ > 1) {
    const Framebuffer resolved = createColorDepth(width_, height_, 1);
    blitColorTo(resolved.id(), {width_, height_});
    return resolved.readPixelsRGBA();
  }
  WaitRecording::record(&SyncCounts::readbacks, "readPixels");
  const std::size_t row = static_cast<std::size_t>(width_) * 4;
  std::vector<std::uint8_t> pixels(row * static_cast<std::size_t>(height_));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(color_.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(pixels.size()), pixels.data());
  checkDebugErrors();
  // GL stores the bottom row first; images start at the top.
  std::vector<std::uint8_t> swap(row);
  for (int y = 0; y < height_ / 2; ++y) {
    std::uint8_t* top = pixels.data() + static_cast<std::size_t>(y) * row;
    std::uint8_t* bottom = pixels.data() + static_cast<std::size_t>(height_ - 1 - y) * row;
    std::memcpy(swap.data(), top, row);
    std::memcpy(top, bottom, row);
    std::memcpy(bottom, swap.data(), row);
  }
  return pixels;
}

VertexArray VertexArray::create() {
  VertexArray vertex_array;
  GLuint id = 0;
  glCreateVertexArrays(1, &id);
  vertex_array.name_ = UniqueName<VertexArrayDeleter>(id);
  checkDebugErrors();
  return vertex_array;
}

void VertexArray::bind() const {
  glBindVertexArray(id());
}

// ---- Query

Query Query::create(GLenum target) {
  Query query;
  GLuint id = 0;
  glCreateQueries(target, 1, &id);
  query.name_ = UniqueName<QueryDeleter>(id);
  query.target_ = target;
  checkDebugErrors();
  return query;
}

void Query::begin() const {
  glBeginQuery(target_, id());
  checkDebugErrors();
}

void Query::end() const {
  glEndQuery(target_);
  checkDebugErrors();
}

void Query::timestamp() const {
  glQueryCounter(id(), GL_TIMESTAMP);
  checkDebugErrors();
}

bool Query::resultAvailable() const {
  GLint available = GL_FALSE;
  glGetQueryObjectiv(id(), GL_QUERY_RESULT_AVAILABLE, &available);
  return available == GL_TRUE;
}

std::uint64_t Query::result() const {
  if (!resultAvailable()) WaitRecording::record(&SyncCounts::readbacks, "query");
  GLuint64 value = 0;
  glGetQueryObjectui64v(id(), GL_QUERY_RESULT, &value);
  checkDebugErrors();
  return value;
}

// ---- Fence

Fence Fence::insert() {
  Fence fence;
  fence.sync_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  checkDebugErrors();
  if (fence.sync_ == nullptr) throw GlError("glFenceSync failed");
  return fence;
}

Fence::Fence(Fence&& other) noexcept : sync_(std::exchange(other.sync_, nullptr)) {}

Fence& Fence::operator=(Fence&& other) noexcept {
  if (this != &other) {
    if (sync_) glDeleteSync(sync_);
    sync_ = std::exchange(other.sync_, nullptr);
  }
  return *this;
}

Fence::~Fence() {
  if (sync_) glDeleteSync(sync_);
}

bool Fence::signalled() const {
  if (!sync_) return true;
  // GL_SYNC_FLUSH_COMMANDS_BIT: a fence still in the client's queue would otherwise never signal.
  return glClientWaitSync(sync_, GL_SYNC_FLUSH_COMMANDS_BIT, 0) != GL_TIMEOUT_EXPIRED;
}

void Fence::wait() const {
  if (signalled()) return;
  WaitRecording::record(&SyncCounts::fence_waits, "fence");
  constexpr GLuint64 kSecond = 1'000'000'000;
  for (;;) {
    const GLenum status = glClientWaitSync(sync_, GL_SYNC_FLUSH_COMMANDS_BIT, kSecond);
    if (status == GL_ALREADY_SIGNALED || status == GL_CONDITION_SATISFIED) return;
    if (status == GL_WAIT_FAILED) throw GlError("glClientWaitSync failed");
  }
}

}  // namespace drape::gl
