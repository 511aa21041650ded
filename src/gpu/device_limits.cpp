#include "gpu/device_limits.hpp"

#include "core/cloth_mesh.hpp"
#include "gl/gl.hpp"
#include "gpu/colliders.hpp"
#include "gpu/layout.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

namespace drape::gpu {

namespace {

std::string mebibytes(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / (1024.0 * 1024.0));
  return text;
}

std::uint64_t springCount(const ClothSpec& c, SpringType type) {
  if (c.mesh)
    return std::uint64_t(std::count_if(c.mesh->springs.begin(), c.mesh->springs.end(),
                                       [type](const MeshSpring& s) { return s.type == type; }));
  const std::uint64_t W = std::uint64_t(c.num_width_points), H = std::uint64_t(c.num_height_points);
  switch (type) {
    case SpringType::Structural:
      return 2 * W * H - W - H;
    case SpringType::Shearing:
      return 2 * (W - 1) * (H - 1);
    case SpringType::Bending:
      return 2 * W * H - 2 * W - 2 * H;
  }
  return 0;
}

GLint integer(GLenum what) {
  GLint value = 0;
  glGetIntegerv(what, &value);
  return value;
}

GLint integerAt(GLenum what, GLuint index) {
  GLint value = 0;
  glGetIntegeri_v(what, index, &value);
  return value;
}

}  // namespace

DeviceLimits queryDeviceLimits(std::size_t max_buffer_bytes, bool software) {
  DeviceLimits d;
  d.shared_bytes = std::uint64_t(integer(GL_MAX_COMPUTE_SHARED_MEMORY_SIZE));
  d.group_invocations = std::uint32_t(integer(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS));
  d.group_size_x = std::uint32_t(integerAt(GL_MAX_COMPUTE_WORK_GROUP_SIZE, 0));
  d.max_groups_x = std::uint32_t(integerAt(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0));
  d.max_groups_y = std::uint32_t(integerAt(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 1));
  GLint64 block = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
  d.max_buffer_bytes = max_buffer_bytes ? max_buffer_bytes : std::uint64_t(block);
  d.buffer_limit_is_option = max_buffer_bytes != 0;
  d.storage_bindings = integer(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS);
  d.software = software;
  return d;
}

void checkLimits(const Scene& scene, const SceneNeeds& needs, std::uint32_t buckets, const DeviceLimits& device) {
  const ClothSpec& c = scene.cloth;
  const std::uint64_t n = std::uint64_t(c.pointCount());
  std::uint64_t springs = 0;
  for (int t = 0; t < kSpringTypeCount; ++t)
    if (needs.springs[std::size_t(t)]) springs += springCount(c, SpringType(t));
  const std::uint64_t limit = device.max_buffer_bytes;
  const std::string cloth =
      c.mesh ? std::to_string(n) + "-point mesh cloth"
             : std::to_string(c.num_width_points) + "x" + std::to_string(c.num_height_points) + " cloth";
  struct Need {
    const char* what;
    std::uint64_t bytes;
  };
  const Need needed[] = {
      {"positions", n * sizeof(glm::vec4)},
      {"point masses", n * sizeof(PointMass)},
      {"spring adjacency", 2 * springs * sizeof(Neighbor)},
      {"coloured springs", springs * sizeof(ColouredSpring)},
      {"hash-grid points", needs.contacts ? n * sizeof(GridPoint) : 0},
      {"hash-grid buckets", needs.contacts ? (std::uint64_t(buckets) + 1) * sizeof(std::uint32_t) : 0},
      {"self-collision anchors", needs.contacts ? n * sizeof(glm::vec4) : 0},
      {"colliders and mesh distance fields", colliderCount(scene) * sizeof(Collider)},
  };
  for (const Need& need : needed)
    if (need.bytes > limit)
      throw GpuLimitError("gpu solver: a " + cloth + " needs " + mebibytes(need.bytes) + " for its " + need.what +
                          ", more than the " + mebibytes(limit) + " one shader storage buffer may hold here" +
                          (device.buffer_limit_is_option ? " (GpuSolverOptions::max_buffer_bytes)"
                                                         : " (GL_MAX_SHADER_STORAGE_BLOCK_SIZE)"));
  static_assert(kMaxClothPoints <= kNeighborIndexMask + 1LL, "point indices must fit Neighbor::index_type");
  if (device.storage_bindings < int(kBindingCount))
    throw GpuLimitError("gpu solver: needs " + std::to_string(kBindingCount) +
                        " shader storage binding points, this GPU has " + std::to_string(device.storage_bindings) +
                        " (GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS)");
  const std::uint64_t groups = (n + kLocalSize - 1) / kLocalSize;
  if (groups > std::uint64_t(device.max_groups_x) * std::uint64_t(device.max_groups_y))
    throw GpuLimitError("gpu solver: a " + cloth + " needs " + std::to_string(groups) +
                        " work groups, more than GL_MAX_COMPUTE_WORK_GROUP_COUNT allows");
  if ((buckets + kScanBlock - 1) / kScanBlock > device.max_groups_x)
    throw GpuLimitError("gpu solver: " + std::to_string(buckets) + " hash-grid buckets need more scan work groups " +
                        "than GL_MAX_COMPUTE_WORK_GROUP_COUNT allows");
}

}  // namespace drape::gpu
