// Move-only RAII wrappers of GL objects (Magnum style): deleted copy, noexcept move, the destructor
// deletes, id() gives the name. A default-constructed object is empty (id 0) and makes no GL call,
// so these types exist without a context. All creation uses direct state access (GL 4.5).
#pragma once

#include "gl/debug.hpp"
#include "gl/gl.hpp"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace drape::gl {

// Shared by every wrapper: owns one GL name, deleted by Deleter, 0 when empty or moved from.
template <class Deleter>
class UniqueName {
 public:
  UniqueName() = default;
  explicit UniqueName(GLuint id) : id_(id) {}
  UniqueName(const UniqueName&) = delete;
  UniqueName& operator=(const UniqueName&) = delete;
  UniqueName(UniqueName&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
  UniqueName& operator=(UniqueName&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, 0);
    }
    return *this;
  }
  ~UniqueName() { reset(); }

  GLuint get() const { return id_; }
  GLuint release() noexcept { return std::exchange(id_, 0); }  // gives up ownership without deleting
  void reset() noexcept {
    if (id_ != 0) Deleter{}(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

struct BufferDeleter {
  void operator()(GLuint id) const noexcept { glDeleteBuffers(1, &id); }
};
struct ProgramDeleter {
  void operator()(GLuint id) const noexcept { glDeleteProgram(id); }
};
struct TextureDeleter {
  void operator()(GLuint id) const noexcept { glDeleteTextures(1, &id); }
};
struct RenderbufferDeleter {
  void operator()(GLuint id) const noexcept { glDeleteRenderbuffers(1, &id); }
};
struct FramebufferDeleter {
  void operator()(GLuint id) const noexcept { glDeleteFramebuffers(1, &id); }
};
struct VertexArrayDeleter {
  void operator()(GLuint id) const noexcept { glDeleteVertexArrays(1, &id); }
};
struct QueryDeleter {
  void operator()(GLuint id) const noexcept { glDeleteQueries(1, &id); }
};

// Immutable storage (glNamedBufferStorage). upload() needs GL_DYNAMIC_STORAGE_BIT in flags.
class Buffer {
 public:
  Buffer() = default;
  // bytes may be 0 (an empty pin list is legitimate): GL rejects zero-sized storage, so a few bytes
  // are allocated and size() still reports 0.
  static Buffer create(std::size_t bytes, const void* data = nullptr, GLbitfield flags = GL_DYNAMIC_STORAGE_BIT);
  template <class T>
  static Buffer fromVector(const std::vector<T>& values, GLbitfield flags = GL_DYNAMIC_STORAGE_BIT) {
    static_assert(std::is_trivially_copyable_v<T>, "buffer contents are copied bytewise");
    return create(values.size() * sizeof(T), values.empty() ? nullptr : values.data(), flags);
  }

  GLuint id() const { return name_.get(); }
  std::size_t size() const { return size_; }  // bytes

  // Throws std::out_of_range when [offset, offset + bytes) is outside the buffer.
  void upload(std::size_t offset, std::size_t bytes, const void* data);
  template <class T>
  void upload(const std::vector<T>& values, std::size_t offset_elements = 0) {
    static_assert(std::is_trivially_copyable_v<T>, "buffer contents are copied bytewise");
    upload(offset_elements * sizeof(T), values.size() * sizeof(T), values.data());
  }

  // The explicit, named read-back to the CPU (glGetNamedBufferSubData; waits for the GPU).
  // Throws std::out_of_range when the range is outside the buffer.
  template <class T>
  std::vector<T> download(std::size_t count, std::size_t offset_elements = 0) const {
    static_assert(std::is_trivially_copyable_v<T>, "buffer contents are copied bytewise");
    std::vector<T> values(count);
    downloadBytes(offset_elements * sizeof(T), count * sizeof(T), values.data());
    return values;
  }
  void downloadBytes(std::size_t offset, std::size_t bytes, void* out) const;

  // A buffer the GPU writes (copyTo) and the CPU reads through a persistent, coherent mapping: once a
  // fence placed after the copy has signalled, mapped() holds the data and reading it waits for nothing.
  static Buffer createReadMapped(std::size_t bytes);
  const void* mapped() const { return mapped_; }

  void bindBase(GLenum target, GLuint index) const;  // GL_SHADER_STORAGE_BUFFER, GL_UNIFORM_BUFFER, ...
  void clear();                                      // every byte to zero, on the GPU
  // GPU-side copy (glCopyNamedBufferSubData); throws std::out_of_range on a bad range.
  void copyTo(Buffer& target, std::size_t source_offset, std::size_t target_offset, std::size_t bytes) const;

 private:
  UniqueName<BufferDeleter> name_;
  std::size_t size_ = 0;
  const void* mapped_ = nullptr;  // unmapped by GL when the buffer is deleted
};

// A linked program with its table of active uniforms. Setting a uniform the program does not have
// (or with the wrong type) throws GlError: a misspelt name is an error, not silence. Code paths
// removed by #defines remove their uniforms too; setUniformOptional is for those.
// Uniforms are set with glProgramUniform*, so the program need not be in use.
class Program {
 public:
  Program() noexcept = default;  // the uniform table allocates nothing until a program is linked
  // Takes ownership of a successfully linked program; label names it in error messages.
  Program(GLuint linked_program, std::string label);

  GLuint id() const { return name_.get(); }
  const std::string& label() const { return label_; }
  bool isCompute() const { return compute_; }
  bool hasUniform(const char* name) const;

  void use() const;
  void dispatch(glm::uvec3 groups) const;  // use() + glDispatchCompute
  // use() + glDispatchComputeIndirect: the group counts are read, on the GPU, from the buffer bound to
  // GL_DISPATCH_INDIRECT_BUFFER at `offset` bytes.
  void dispatchIndirect(std::size_t offset) const;
  glm::uvec3 localSize() const;  // GL_COMPUTE_WORK_GROUP_SIZE; throws GlError if not compute
  // Work groups along x that cover `invocations` threads with this program's local size.
  glm::uvec3 groupsFor(std::uint32_t invocations) const;

  // One overload per GLSL type; pass exactly that C++ type (1u for uint, 1.0f for float).
  void setUniform(const char* name, int value) const;
  void setUniform(const char* name, unsigned value) const;
  void setUniform(const char* name, float value) const;
  void setUniform(const char* name, double value) const;  // a GLSL double (GL 4.0)
  void setUniform(const char* name, bool value) const;
  void setUniform(const char* name, const glm::vec2& value) const;
  void setUniform(const char* name, const glm::vec3& value) const;
  void setUniform(const char* name, const glm::vec4& value) const;
  void setUniform(const char* name, const glm::ivec3& value) const;
  void setUniform(const char* name, const glm::uvec2& value) const;
  void setUniform(const char* name, const std::vector<float>& values) const;  // a float[], from element 0
  void setUniform(const char* name, const glm::mat3& value) const;
  void setUniform(const char* name, const glm::mat4& value) const;

  // Same, but a uniform the program does not have is skipped (a wrong type still throws).
  template <class T>
  void setUniformOptional(const char* name, const T& value) const {
    if (hasUniform(name)) setUniform(name, value);
  }

 private:
  struct Uniform {
    GLint location = -1;
    GLenum type = 0;
    GLint size = 1;  // elements, for an array
  };
  GLint locate(const char* name, GLenum type) const;

  UniqueName<ProgramDeleter> name_;
  std::string label_;
  bool compute_ = false;
  glm::uvec3 local_size_{0};
  std::unordered_map<std::string, Uniform> uniforms_;
};

// 2D textures, multisampled 2D textures and cube maps with immutable storage.
class Texture {
 public:
  Texture() = default;
  static Texture create2D(int width, int height, GLenum internal_format, int levels = 1);
  static Texture create2DMultisample(int width, int height, GLenum internal_format, int samples);
  static Texture createCube(int size, GLenum internal_format, int levels = 1);
  // Mip levels for a full chain down to 1x1.
  static int fullMipLevels(int width, int height);

  GLuint id() const { return name_.get(); }
  GLenum target() const { return target_; }
  int width() const { return width_; }
  int height() const { return height_; }
  int levels() const { return levels_; }

  // Whole level; rows bottom to top as GL expects. format/type describe `pixels` (GL_RGBA, GL_UNSIGNED_BYTE).
  void upload2D(GLenum format, GLenum type, const void* pixels, int level = 0);
  // face in GL order: +X, -X, +Y, -Y, +Z, -Z (0..5).
  void uploadCubeFace(int face, GLenum format, GLenum type, const void* pixels, int level = 0);
  void bind(GLuint unit) const;
  void generateMipmaps();
  // GL_TEXTURE_CUBE_MAP_SEAMLESS is global state and belongs to the renderer, not here.
  void setSampling(GLenum min_filter, GLenum mag_filter, GLenum wrap = GL_REPEAT);

 private:
  UniqueName<TextureDeleter> name_;
  GLenum target_ = 0;
  int width_ = 0;
  int height_ = 0;
  int levels_ = 0;
};

class Renderbuffer {
 public:
  Renderbuffer() = default;
  static Renderbuffer create(int width, int height, GLenum internal_format, int samples = 1);
  GLuint id() const { return name_.get(); }

 private:
  UniqueName<RenderbufferDeleter> name_;
};

// An offscreen target: one RGBA8 color texture and a depth renderbuffer of the same size/samples.
class Framebuffer {
 public:
  Framebuffer() = default;
  // samples > 1 makes a multisampled target; readPixelsRGBA resolves it first.
  static Framebuffer createColorDepth(int width, int height, int samples = 1);
  // The most samples createColorDepth can give in the current context (GL_MAX_SAMPLES for the depth
  // renderbuffer, GL_MAX_COLOR_TEXTURE_SAMPLES for the colour texture, whichever is smaller).
  static int maxSamples();

  GLuint id() const { return name_.get(); }
  int width() const { return width_; }
  int height() const { return height_; }
  int samples() const { return samples_; }
  const Texture& colorTexture() const { return color_; }

  void bind() const;          // as GL_FRAMEBUFFER, and sets the viewport to its size
  static void bindDefault();  // the window's framebuffer (no viewport change)
  // Resolves/copies color into another framebuffer (0: the window), scaled to target_size.
  void blitColorTo(GLuint target_framebuffer, glm::ivec2 target_size) const;
  // Width*height*4 bytes, rows top to bottom (image order, ready for stb_image_write).
  std::vector<std::uint8_t> readPixelsRGBA() const;

 private:
  UniqueName<FramebufferDeleter> name_;
  Texture color_;
  Renderbuffer depth_;
  int width_ = 0;
  int height_ = 0;
  int samples_ = 1;
};

// Empty vertex array: the renderer pulls vertices from SSBOs with gl_VertexID.
class VertexArray {
 public:
  VertexArray() = default;
  static VertexArray create();
  GLuint id() const { return name_.get(); }
  void bind() const;

 private:
  UniqueName<VertexArrayDeleter> name_;
};

// A GPU timer (GL_TIME_ELAPSED by default). Only one GL_TIME_ELAPSED query may be active at a time.
class Query {
 public:
  Query() = default;
  static Query create(GLenum target = GL_TIME_ELAPSED);
  GLuint id() const { return name_.get(); }

  void begin() const;
  void end() const;
  void timestamp() const;  // glQueryCounter: the GPU's clock once every command before it has run
  bool resultAvailable() const;
  // Nanoseconds (GL_TIME_ELAPSED: a duration; GL_TIMESTAMP: a time). Waits until available, which is
  // counted as a synchronous read-back when it was not.
  std::uint64_t result() const;

 private:
  UniqueName<QueryDeleter> name_;
  GLenum target_ = 0;
};

// A point in the command stream (glFenceSync). Move-only; deletes its sync object.
class Fence {
 public:
  Fence() = default;
  static Fence insert();  // after every command issued so far
  Fence(const Fence&) = delete;
  Fence& operator=(const Fence&) = delete;
  Fence(Fence&& other) noexcept;
  Fence& operator=(Fence&& other) noexcept;
  ~Fence();

  bool empty() const { return sync_ == nullptr; }
  bool signalled() const;  // polls, never waits
  // Blocks until the GPU has passed the fence (counted in SyncCounts::fence_waits when it had not yet).
  void wait() const;

 private:
  GLsync sync_ = nullptr;
};

// Every way this thread made the CPU wait for the GPU, counted since it started. A steady-state frame of
// `drape simulate` or `drape view` adds nothing to `readbacks` or `finishes`: the GPU's answers come a
// frame late through fences (tests/gpu_solver_gl_test.cpp holds that).
struct SyncCounts {
  long long readbacks = 0;    // Buffer::download, Framebuffer::readPixelsRGBA, Query::result not yet available
  long long finishes = 0;     // gl::finish()
  long long fence_waits = 0;  // Fence::wait() on a fence the GPU had not yet passed
};
SyncCounts syncCounts();
void finish();  // glFinish, counted: only where a timing or an explicit read asks for it

// Whether GL_TIME_ELAPSED measures compute dispatches on the current context: times one small
// dispatch and reports whether the result is plausible (>= 1 us). llvmpipe reads a token 1 ns for
// any query (docs/design.md, section 8, calls it 0), so callers time with the wall clock around glFinish instead.
// Probed once per process (the first context decides); defined in shader.cpp since it compiles its
// own probe program.
bool timerQueriesWork();

// Records every compute dispatch this thread issues through Program::dispatch (or dispatchIndirect), and
// every synchronous wait of SyncCounts, while it lives (the innermost one, when nested). It counts what
// really reaches GL, so tests can hold a solver's own account of its passes against it.
class DispatchRecorder {
 public:
  struct Dispatch {
    std::string program;   // Program::label()
    glm::uvec3 groups{0};  // 0 for an indirect dispatch: its sizes are in a GPU buffer
    bool indirect = false;
  };
  struct Wait {
    std::string what;  // "download", "readPixels", "query", "finish", "fence"
  };
  DispatchRecorder();
  ~DispatchRecorder();
  DispatchRecorder(const DispatchRecorder&) = delete;
  DispatchRecorder& operator=(const DispatchRecorder&) = delete;

  const std::vector<Dispatch>& dispatches() const { return dispatches_; }
  // Each synchronous wait of SyncCounts, in order, while the recorder lived.
  const std::vector<Wait>& waits() const { return waits_; }
  void clear() {
    dispatches_.clear();
    waits_.clear();
  }

 private:
  friend class Program;
  friend struct WaitRecording;
  std::vector<Dispatch> dispatches_;
  std::vector<Wait> waits_;
  DispatchRecorder* outer_ = nullptr;
};

}  // namespace drape::gl
