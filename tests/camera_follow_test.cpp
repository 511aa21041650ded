// The default camera beyond the look-ahead (render/camera_follow.hpp): it holds still while the cloth stays
// within what it frames, widens smoothly and only widens when the cloth goes further, and keeps a cloth that
// moves steadily in view even a frame late (the viewer's case). Also the look-ahead's work budget and the
// floor that only goes down (render/framing.hpp). Pure maths, no GL.
#include "render/camera_follow.hpp"
#include "cpu/cpu_solver.hpp"
#include "render/framing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace drape {
namespace {

constexpr float kAspect = 640.0f / 480.0f;

// A flat n x n cloth of side 1 at height y, its corner at (x, 0, z).
std::vector<glm::dvec3> sheet(glm::dvec3 corner, int n = 9) {
  std::vector<glm::dvec3> x;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      x.push_back(corner + glm::dvec3(double(i) / (n - 1), 0.0, double(j) / (n - 1)));
  return x;
}

FramingSubject subjectOf(const std::vector<glm::dvec3>& x) {
  FramingSubject s;
  for (const glm::dvec3& p : x)
    s.points.push_back(glm::vec3(p));
  return s;
}

// The largest of |ndc.x|, |ndc.y| over the points: 1 is the image's edge.
float reachInImage(const Camera& camera, const std::vector<glm::dvec3>& x) {
  const glm::mat4 vp = camera.viewProjection(kAspect);
  float most = 0.0f;
  for (const glm::dvec3& p : x) {
    const glm::vec4 clip = vp * glm::vec4(glm::vec3(p), 1.0f);
    EXPECT_GT(clip.w, 0.0f);
    most = std::max({most, std::abs(clip.x / clip.w), std::abs(clip.y / clip.w)});
  }
  return most;
}

TEST(CameraFollow, StartsAsTheLookAheadsFramingAndHoldsStillWhileTheClothStaysWithinIt) {
  const std::vector<glm::dvec3> start = sheet({0, 0, 0});
  CameraFollow follow(subjectOf(start), kAspect);
  Camera framed;
  framed.frame(subjectOf(start), kAspect);
  EXPECT_LT(glm::distance(follow.camera().position(), framed.position()), 1e-5f);
  EXPECT_NEAR(follow.camera().distance(), framed.distance(), 1e-5f);
  const glm::vec3 eye = follow.camera().position();
  // The cloth shrinks towards its centre and comes back: nothing it needs lies further out.
  for (int frame = 1; frame <= 60; ++frame) {
    std::vector<glm::dvec3> x = start;
    const double shrink = 0.5 + 0.5 * std::cos(0.2 * frame);
    for (glm::dvec3& p : x)
      p = glm::dvec3(0.5, 0.0, 0.5) + shrink * (p - glm::dvec3(0.5, 0.0, 0.5));
    follow.next(reachOf(x, follow.frame()));
    EXPECT_EQ(follow.camera().position(), eye) << "frame " << frame << ": never closer, never drifting";
  }
}

// A cloth sliding steadily away to the right and down, 1% of its size a frame: the camera widens ahead
// of it, a little each frame, only ever outwards, and the viewer's camera (a frame late) keeps it inside
// the image.
TEST(CameraFollow, WidensSmoothlyAndOnlyOutwardsToKeepAMovingClothInView) {
  CameraFollow follow(subjectOf(sheet({0, 0, 0})), kAspect);
  const glm::vec3 back = Camera::defaultAxes().back;
  float last_depth = glm::dot(follow.camera().position(), back);
  std::array<float, ViewReach::kValues> held = follow.held().values();
  float largest_step = 0.0f;
  glm::vec3 eye = follow.camera().position();
  for (int frame = 1; frame <= 150; ++frame) {
    const std::vector<glm::dvec3> before = sheet({0.01 * (frame - 1), -0.005 * (frame - 1), 0});
    const std::vector<glm::dvec3> now = sheet({0.01 * frame, -0.005 * frame, 0});
    follow.next(reachOf(before, follow.frame()));
    const Camera camera = follow.camera();
    EXPECT_LT(reachInImage(camera, now), 1.0f) << "frame " << frame << ": the cloth left the image";
    const std::array<float, ViewReach::kValues> h = follow.held().values();
    for (int k = 0; k < ViewReach::kValues; ++k)
      EXPECT_GE(h[k], held[k]) << "frame " << frame << ", value " << k << ": what the camera holds shrank";
    held = h;
    const float depth = glm::dot(camera.position(), back);
    EXPECT_GE(depth, last_depth) << "frame " << frame << ": the camera came closer";
    last_depth = depth;
    largest_step = std::max(largest_step, glm::distance(camera.position(), eye) / camera.distance());
    eye = camera.position();
  }
  EXPECT_GT(glm::distance(eye, CameraFollow(subjectOf(sheet({0, 0, 0})), kAspect).camera().position()), 0.1f)
      << "the camera moved to follow";
  // Eased at most kMaxEase of the distance a frame, and what the cloth needs at once is its own travel.
  EXPECT_LT(largest_step, 0.03f) << "the camera jumped";
}

// The window grows wider: the camera keeps what it held and frames it at the new aspect ratio.
TEST(CameraFollow, AWiderWindowKeepsWhatTheCameraHeld) {
  const std::vector<glm::dvec3> start = sheet({0, 0, 0}), far = sheet({1.5, -0.5, 0.5});
  CameraFollow follow(subjectOf(start), kAspect);
  for (int frame = 0; frame < 40; ++frame)
    follow.next(reachOf(far, follow.frame()));
  follow.setAspect(2.0f);
  const glm::mat4 vp = follow.camera().viewProjection(2.0f);
  for (const auto* x : {&start, &far})
    for (const glm::dvec3& p : *x) {
      const glm::vec4 clip = vp * glm::vec4(glm::vec3(p), 1.0f);
      EXPECT_LT(std::max(std::abs(clip.x), std::abs(clip.y)) / clip.w, 1.0f);
    }
}

TEST(LookAhead, IsBoundedByWorkNotTime) {
  Scene scene;
  scene.sim.frames_per_sec = 30.0;
  scene.sim.steps_per_frame = 30;
  EXPECT_EQ(lookAheadFrames(scene, 2500), 40) << "3'000'000 point-substeps of a 50 x 50 cloth";
  EXPECT_EQ(lookAheadFrames(scene, 100), 60) << "a small cloth: the first 2 s, no more";
  EXPECT_EQ(lookAheadFrames(scene, 2500, 2500 * 30 - 1), 0) << "not even one frame: none";
  EXPECT_EQ(lookAheadFrames(scene, 2500, 2500 * 30), 1);
  scene.sim.steps_per_frame = 60;
  EXPECT_EQ(lookAheadFrames(scene, 2500), 20) << "twice the substeps, half the frames";
}

// The look-ahead steps the solver it is given, sees every frame, frames exactly those, and leaves the solver
// at its start for the run.
TEST(LookAhead, FramesTheFramesItSteppedAndResetsTheSolver) {
  Scene scene;
  scene.cloth.num_width_points = 8;
  scene.cloth.num_height_points = 8;
  CpuSolver<float> solver(scene), run(scene);
  SceneExtent extent(scene, solver.topology()), expected(scene, run.topology());
  std::vector<int> seen;
  EXPECT_EQ(lookAhead(extent, solver, 5, [&](int frame, const std::vector<glm::dvec3>&) { seen.push_back(frame); }), 5);
  EXPECT_EQ(seen, (std::vector<int>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(solver.substeps(), 0) << "reset for the run";
  for (int frame = 1; frame <= 5; ++frame) {
    run.stepFrame();
    expected.addCloth(run.readPositions());
  }
  EXPECT_EQ(extent.clothFrames(), expected.clothFrames());
  EXPECT_EQ(extent.subject().points, expected.subject().points);
}

TEST(GroundBelow, OnlyEverGoesDownAndLeavesTheScenesPlane) {
  const Ground floor{{0.0f, -1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, false};
  EXPECT_EQ(groundBelow(floor, Bounds{{0, 0, 0}, {1, 1, 1}}).point, floor.point) << "everything is above it";
  const Ground lower = groundBelow(floor, Bounds{{0, -2, 0}, {1, 1, 1}});
  EXPECT_LT(lower.point.y, -2.0f) << "below the lowest point, with a gap";
  EXPECT_GT(lower.point.y, -2.2f);
  const Ground plane{{0.0f, -1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, true};
  EXPECT_EQ(groundBelow(plane, Bounds{{0, -2, 0}, {1, 1, 1}}).point, plane.point) << "a collider stays where it is";
}

}  // namespace
}  // namespace drape
