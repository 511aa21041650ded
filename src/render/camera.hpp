// Orbit camera: it circles a target point at a distance, with yaw around the world y axis and pitch
// above the horizon; pan moves the target in the view plane; zoom scales the distance.
#pragma once

#include <glm/glm.hpp>

#include <vector>

namespace drape {

struct Bounds {
  glm::vec3 min{0.0f};
  glm::vec3 max{0.0f};
  glm::vec3 centre() const { return 0.5f * (min + max); }
  float radius() const { return 0.5f * glm::length(max - min); }  // of the enclosing sphere
  void include(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
};

// What the default camera frames: points (the cloth at rest, mesh obstacles' vertices, the cloth's
// footprint on each plane) and spheres. A sphere's own silhouette is framed, not its box: the empty
// corners of a box around cloth and sphere left the subject a small part of the frame.
struct FramingSubject {
  std::vector<glm::vec3> points;
  std::vector<glm::vec4> spheres;  // centre xyz, radius w
  Bounds bounds() const;           // of everything; the camera looks at its centre
};

struct Ray {
  glm::vec3 origin;
  glm::vec3 direction;  // unit
};

// The default view's axes in world space: right and up across the image, back towards the camera.
struct ViewAxes {
  glm::vec3 right, up, back;
};

class Camera {
 public:
  static constexpr float kDefaultYaw = 0.35f;   // rad, a little to the right of +z
  static constexpr float kDefaultPitch = 0.6f;  // rad above the horizon
  static constexpr float kFovY = 0.7854f;       // rad (45 degrees)
  static constexpr float kFill = 0.92f;         // of the half-width and half-height a framed box may reach
  // A view wider than this frames as this: `render` (640x480) and a wider viewer window get the same
  // camera, the wider one showing more on each side.
  static constexpr float kFramingAspect = 4.0f / 3.0f;

  static ViewAxes defaultAxes();

  // Looks at the subject from the default direction, as close as keeps every point and every sphere
  // inside kFill of the view at this aspect ratio (at most kFramingAspect), centred: the subject's
  // wider side nearly fills the frame.
  void frame(const FramingSubject& subject, float aspect);
  // The same for the eight corners of a box.
  void frame(const Bounds& bounds, float aspect);

  void orbit(float d_yaw, float d_pitch);  // rad; pitch stays short of the poles
  // Moves the target by a drag of (dx, dy) pixels in a viewport `viewport_height` pixels high, so that
  // the point at the target follows the cursor.
  void pan(float dx, float dy, float viewport_height);
  void zoom(float factor);  // distance *= factor (< 1 moves closer)

  glm::vec3 target() const { return target_; }
  float distance() const { return distance_; }
  glm::vec3 position() const;
  glm::mat4 view() const;
  glm::mat4 projection(float aspect) const;  // near/far follow the distance so depth stays precise
  glm::mat4 viewProjection(float aspect) const { return projection(aspect) * view(); }

  // The ray through a pixel (origin top-left, as window systems report the cursor).
  Ray rayThrough(glm::vec2 pixel, glm::ivec2 viewport) const;

 private:
  glm::vec3 target_{0.5f, 0.5f, 0.5f};
  float distance_ = 3.0f;
  float yaw_ = kDefaultYaw;
  float pitch_ = kDefaultPitch;
  float scene_radius_ = 1.0f;
};

}  // namespace drape
