#include "render/cloth_surface.hpp"

#include <algorithm>
#include <cmath>

namespace drape {

namespace {

bool isQuad(const glm::uvec4& face) {
  return face.w != kNoCorner;
}

// A face's normal (twice its area along it: the cross product of a triangle's edges, of a quad's diagonals)
// and its dP/du, dP/dv from the UVs (Lengyel 2001), scaled by the face's size rather than divided by its UV
// area, so that every face counts in proportion to its size; only the UV determinant's sign is used.
struct FaceFrame {
  glm::vec3 normal, tangent, bitangent;
};

FaceFrame faceFrame(const glm::uvec4& f, const std::vector<glm::vec4>& x, const std::vector<glm::vec2>& uv) {
  const bool quad = isQuad(f);
  const std::uint32_t a = f.x, b = quad ? f.z : f.y, c = quad ? f.y : f.x, d = quad ? f.w : f.z;
  const glm::vec3 e1 = glm::vec3(x[b]) - glm::vec3(x[a]), e2 = glm::vec3(x[d]) - glm::vec3(x[c]);
  const glm::vec2 d1 = uv[b] - uv[a], d2 = uv[d] - uv[c];
  const float s = d1.x * d2.y - d2.x * d1.y < 0.0f ? -1.0f : 1.0f;
  return {glm::cross(e1, e2), s * (e1 * d2.y - e2 * d1.y), s * (e2 * d1.x - e1 * d2.x)};
}

// Unit normal (w 0) and unit tangent made orthogonal to it, the bitangent's handedness in w.
void orthonormalFrame(glm::vec3 n, glm::vec3 t, const glm::vec3& b, glm::vec4& normal, glm::vec4& tangent) {
  const float n_len = glm::length(n);
  n = n_len > 0.0f ? n / n_len : glm::vec3(0.0f, 1.0f, 0.0f);
  t -= n * glm::dot(n, t);
  const float t_len = glm::length(t);
  t = t_len > 0.0f ? t / t_len
                   : glm::normalize(glm::cross(n, std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0)));
  normal = glm::vec4(n, 0.0f);
  tangent = glm::vec4(t, glm::dot(glm::cross(n, t), b) < 0.0f ? -1.0f : 1.0f);
}

float smoothStep(float edge0, float edge1, float x) {
  const float t = std::clamp((x - edge0) / (edge1 - edge0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

}  // namespace

SurfaceLayout buildSurfaceLayout(const Topology& topology) {
  SurfaceLayout layout;
  layout.points = std::uint32_t(topology.pointCount());
  std::vector<glm::uvec4> triangles;
  for (const auto& f : topology.faces) {
    const glm::uvec4 face{f[0], f[1], f[2], f[3]};
    (isQuad(face) ? layout.faces : triangles).push_back(face);
  }
  if (topology.faces.empty())  // a topology made without faces: its triangles, as they are
    for (std::size_t t = 0; t + 2 < topology.triangles.size(); t += 3)
      triangles.emplace_back(topology.triangles[t], topology.triangles[t + 1], topology.triangles[t + 2], kNoCorner);
  layout.quads = std::uint32_t(layout.faces.size());
  layout.faces.insert(layout.faces.end(), triangles.begin(), triangles.end());

  layout.face_offsets.assign(layout.points + 1, 0);
  for (const glm::uvec4& f : layout.faces)
    for (int k = 0; k < (isQuad(f) ? 4 : 3); ++k)
      ++layout.face_offsets[f[k] + 1];
  for (std::uint32_t i = 0; i < layout.points; ++i)
    layout.face_offsets[i + 1] += layout.face_offsets[i];
  layout.point_faces.resize(layout.face_offsets.back());
  std::vector<std::uint32_t> fill(layout.face_offsets.begin(), layout.face_offsets.end() - 1);
  for (std::uint32_t f = 0; f < layout.faces.size(); ++f)
    for (int k = 0; k < (isQuad(layout.faces[f]) ? 4 : 3); ++k)
      layout.point_faces[fill[layout.faces[f][k]]++] = f;

  const auto& x = topology.initial_positions;
  layout.uvs = topology.uvs;
  layout.triangles.reserve(std::size_t(layout.quads) * 12 + triangles.size() * 3);
  for (std::uint32_t q = 0; q < layout.quads; ++q) {
    const glm::uvec4 c = layout.faces[q];
    layout.quad_rest.emplace_back(glm::distance(x[c.x], x[c.z]), glm::distance(x[c.y], x[c.w]));
    layout.uvs.push_back(0.25f * (topology.uvs[c.x] + topology.uvs[c.y] + topology.uvs[c.z] + topology.uvs[c.w]));
    const std::uint32_t centre = layout.points + q;
    layout.triangles.insert(layout.triangles.end(),
                            {c.x, c.y, centre, c.y, c.z, centre, c.z, c.w, centre, c.w, c.x, centre});
  }
  for (const glm::uvec4& t : triangles)
    layout.triangles.insert(layout.triangles.end(), {t.x, t.y, t.z});
  return layout;
}

void computeSurface(const SurfaceLayout& layout, const std::vector<glm::vec4>& x, std::vector<glm::vec4>& normals,
                    std::vector<glm::vec4>& tangents, std::vector<glm::vec4>& centres) {
  normals.assign(layout.vertices(), glm::vec4(0.0f));
  tangents.assign(layout.vertices(), glm::vec4(0.0f));
  centres.assign(layout.quads, glm::vec4(0.0f));
  for (std::uint32_t i = 0; i < layout.points; ++i) {
    glm::vec3 n(0.0f), t(0.0f), b(0.0f);
    for (std::uint32_t k = layout.face_offsets[i]; k < layout.face_offsets[i + 1]; ++k) {
      const FaceFrame f = faceFrame(layout.faces[layout.point_faces[k]], x, layout.uvs);
      n += f.normal;
      t += f.tangent;
      b += f.bitangent;
    }
    orthonormalFrame(n, t, b, normals[i], tangents[i]);
  }
  for (std::uint32_t q = 0; q < layout.quads; ++q) {
    const glm::uvec4 c = layout.faces[q];
    const glm::vec3 x0(x[c.x]), x1(x[c.y]), x2(x[c.z]), x3(x[c.w]);
    const glm::vec2 rest = layout.quad_rest[q];
    const float w =
        smoothStep(-kCreaseBlend, kCreaseBlend, glm::distance(x0, x2) / rest.x - glm::distance(x1, x3) / rest.y);
    centres[q] = glm::vec4(0.5f * (w * (x0 + x2) + (1.0f - w) * (x1 + x3)), 1.0f);
    const auto blend = [&](const std::vector<glm::vec4>& v) {
      return w * glm::vec3(v[c.x] + v[c.z]) + (1.0f - w) * glm::vec3(v[c.y] + v[c.w]);
    };
    const FaceFrame face = faceFrame(c, x, layout.uvs);
    const glm::vec3 n = blend(normals);
    orthonormalFrame(glm::length(n) > 0.0f ? n : face.normal, blend(tangents), face.bitangent,
                     normals[layout.points + q], tangents[layout.points + q]);
  }
}

}  // namespace drape
