// The default camera's framing: pure maths, no GL context.
#include "render/camera.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace drape {
namespace {

struct FramingCase {
  const char* name;
  Bounds bounds;
};

// Boxes as scenes make them: the sphere scene (a flat 1 x 1 cloth above a sphere), a flat cloth alone,
// a hanging cloth, a long thin strip, and a box far from the origin.
const FramingCase kCases[] = {
    {"sphere_scene", {{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}}},
    {"flat_cloth", {{0.0f, 1.0f, 0.0f}, {1.0f, 1.0f, 1.0f}}},
    {"hanging_cloth", {{0.0f, 0.0f, 0.5f}, {1.0f, 1.0f, 0.5f}}},
    {"strip", {{-2.0f, 0.0f, 0.0f}, {2.0f, 0.1f, 0.2f}}},
    {"far_away", {{100.0f, -50.0f, 30.0f}, {101.0f, -49.5f, 32.0f}}},
};

class CameraFraming : public ::testing::TestWithParam<FramingCase> {};

// The share of a frame's width that its framed middle takes up, inverted: a frame wider than 4:3 frames its
// middle 4:3 (Camera::kFramingAspect), so a subject filling that spans less of the whole width.
float framedShare(float aspect) {
  return std::max(aspect / Camera::kFramingAspect, 1.0f);
}

// Every corner inside the view, and the box centred with its larger side 90% of the frame across.
TEST_P(CameraFraming, TheBoxFillsTheFrameAndStaysInside) {
  const Bounds& b = GetParam().bounds;
  for (float aspect : {0.5f, 1.0f, 4.0f / 3.0f, 16.0f / 9.0f, 2.5f}) {
    Camera camera;
    camera.frame(b, aspect);
    const glm::mat4 vp = camera.viewProjection(aspect);
    glm::vec2 lo{1e9f}, hi{-1e9f};
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 p{corner & 1 ? b.max.x : b.min.x, corner & 2 ? b.max.y : b.min.y, corner & 4 ? b.max.z : b.min.z};
      const glm::vec4 clip = vp * glm::vec4(p, 1.0f);
      ASSERT_GT(clip.w, 0.0f) << "aspect " << aspect << " corner " << corner << " behind the camera";
      const glm::vec3 ndc = glm::vec3(clip) / clip.w;
      EXPECT_LT(std::abs(ndc.x), 1.0f) << "aspect " << aspect << " corner " << corner;
      EXPECT_LT(std::abs(ndc.y), 1.0f) << "aspect " << aspect << " corner " << corner;
      EXPECT_LT(std::abs(ndc.z), 1.0f) << "aspect " << aspect << " corner " << corner << " clipped by depth";
      lo = glm::min(lo, glm::vec2(ndc));
      hi = glm::max(hi, glm::vec2(ndc));
    }
    // NDC spans 2 across: a span of 1.8 is 90% of the frame, or of its middle 4:3 in a wider one.
    const float span = std::max((hi.x - lo.x) * framedShare(aspect), hi.y - lo.y);
    EXPECT_GE(span, 1.8f) << "aspect " << aspect << ": the box covers " << 50.0f * span << "% of the frame";
  }
}

INSTANTIATE_TEST_SUITE_P(Boxes, CameraFraming, ::testing::ValuesIn(kCases),
                         [](const auto& row) { return std::string(row.param.name); });

// Points on each sphere's surface, dense enough that its silhouette is among them to within 0.3%.
std::vector<glm::vec3> surfaceSamples(const FramingSubject& subject) {
  std::vector<glm::vec3> samples = subject.points;
  for (const glm::vec4& s : subject.spheres)
    for (int i = 0; i <= 40; ++i)
      for (int j = 0; j < 80; ++j) {
        const float theta = 3.14159265f * float(i) / 40.0f, phi = 6.2831853f * float(j) / 80.0f;
        samples.push_back(glm::vec3(s) + s.w * glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                                         std::sin(theta) * std::sin(phi)));
      }
  return samples;
}

// The sphere scene: a flat 50 x 50 cloth one metre up, a sphere of radius 0.2 below it.
FramingSubject sphereScene() {
  FramingSubject subject;
  for (int i = 0; i < 50; ++i)
    for (int j = 0; j < 50; ++j)
      subject.points.push_back({float(i) / 49.0f, 1.0f, float(j) / 49.0f});
  subject.spheres.push_back({0.5f, 0.2f, 0.5f, 0.2f});
  return subject;
}

TEST(CameraFraming, ClothAndSphereFillTheFrameAndStayInside) {
  const FramingSubject subject = sphereScene();
  const std::vector<glm::vec3> samples = surfaceSamples(subject);
  for (float aspect : {0.5f, 1.0f, 4.0f / 3.0f, 16.0f / 9.0f, 2.5f}) {
    Camera camera;
    camera.frame(subject, aspect);
    const glm::mat4 vp = camera.viewProjection(aspect);
    glm::vec2 lo{1e9f}, hi{-1e9f};
    for (const glm::vec3& p : samples) {
      const glm::vec4 clip = vp * glm::vec4(p, 1.0f);
      ASSERT_GT(clip.w, 0.0f);
      const glm::vec3 ndc = glm::vec3(clip) / clip.w;
      ASSERT_LT(std::abs(ndc.x), 1.0f) << "aspect " << aspect;
      ASSERT_LT(std::abs(ndc.y), 1.0f) << "aspect " << aspect;
      ASSERT_LT(std::abs(ndc.z), 1.0f) << "aspect " << aspect;
      lo = glm::min(lo, glm::vec2(ndc));
      hi = glm::max(hi, glm::vec2(ndc));
    }
    const float span = std::max((hi.x - lo.x) * framedShare(aspect), hi.y - lo.y);
    EXPECT_GE(span, 1.8f) << "aspect " << aspect << ": the scene covers " << 50.0f * span << "% of the frame";
    // Wider than 4:3, the camera is the 4:3 one: `render`'s 640x480 and a wide viewer window agree.
    if (aspect > Camera::kFramingAspect) {
      Camera four_by_three;
      four_by_three.frame(subject, Camera::kFramingAspect);
      EXPECT_EQ(camera.distance(), four_by_three.distance()) << "aspect " << aspect;
      EXPECT_EQ(camera.target(), four_by_three.target()) << "aspect " << aspect;
    }
    // Framed as a sphere, not as the box around cloth and sphere: where the height limits the view (a
    // wide frame), the box's empty lower corners would keep the camera away; in a tall frame the
    // cloth's width limits both.
    Camera boxed;
    boxed.frame(subject.bounds(), aspect);
    EXPECT_LE(camera.distance(), boxed.distance() * 1.0001f) << "aspect " << aspect;
    if (aspect >= 4.0f / 3.0f) {
      EXPECT_LT(camera.distance(), 0.9f * boxed.distance()) << "aspect " << aspect;
    }
  }
}

TEST(CameraFraming, ZoomStillMovesAFramedCamera) {
  Camera camera;
  camera.frame(kCases[0].bounds, 4.0f / 3.0f);
  const float framed = camera.distance();
  camera.zoom(2.0f);
  EXPECT_NEAR(camera.distance(), 2.0f * framed, 1e-5f);
}

}  // namespace
}  // namespace drape
