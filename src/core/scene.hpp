// Scene description: the cloth, its colliders and the simulation parameters, as loaded from JSON.
// JSON keys equal field names (scenes/README.md documents each with unit and default).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace drape {

enum class Orientation { Horizontal = 0, Vertical = 1 };
enum class SpringType { Structural = 0, Shearing = 1, Bending = 2 };
enum class StretchScheme { GaussSeidel, Jacobi };
inline const char* stretchSchemeName(StretchScheme s) {
  return s == StretchScheme::GaussSeidel ? "gauss_seidel" : "jacobi";
}
// How a substep moves the points: CS184's explicit Verlet over spring forces; XPBD (Macklin et al. 2016,
// 2019), each spring a distance constraint of compliance 1/k solved on positions; or Vertex Block Descent
// (Chen et al. 2024), a Newton step per point on the implicit-Euler energy (docs/design.md section 2).
enum class Integrator { Verlet, Xpbd, Vbd };
inline constexpr Integrator kIntegrators[] = {Integrator::Verlet, Integrator::Xpbd, Integrator::Vbd};
inline const char* integratorName(Integrator i) {
  return i == Integrator::Verlet ? "verlet" : i == Integrator::Xpbd ? "xpbd" : "vbd";
}
// XPBD and VBD move every point by its external forces first (the prediction x* = x + keep v + a dt^2) and
// then solve the springs implicitly on positions; Verlet integrates the spring forces explicitly.
inline bool isImplicit(Integrator i) {
  return i != Integrator::Verlet;
}
inline constexpr int kSpringTypeCount = 3;

struct ClothMesh;     // core/cloth_mesh.hpp
struct MeshObstacle;  // core/mesh_obstacle.hpp

struct ClothSpec {
  double width = 1.0;                                 // m, along x
  double height = 1.0;                                // m, along z (horizontal) or y (vertical)
  int num_width_points = 50;                          // W >= 2
  int num_height_points = 50;                         // H >= 2
  double thickness = 0.0095;                          // m; self-collision range is 2*thickness
  Orientation orientation = Orientation::Horizontal;  // 0 = horizontal at y = 1, 1 = vertical
  std::vector<glm::ivec2> pinned;                     // [x, y] grid coordinates that never move
  bool enable_structural = true;                      // springs to the left and above
  bool enable_shearing = true;                        // springs to upper-left and upper-right
  bool enable_bending = true;                         // springs two to the left and two above
  double damping = 0.2;                               // percent of the displacement lost per substep
  double density = 150.0;                             // kg/m^2 (the CS184 scenes use 150)
  double ks = 5000.0;                                 // N/m; bending springs use 0.2*ks
  // A cloth from a mesh file instead of a grid (the grid keys above are then unused): read and checked
  // on load, shared by every copy of the scene.
  std::shared_ptr<const ClothMesh> mesh;
  std::string mesh_file;                       // as the scene wrote it, for messages
  std::vector<std::uint32_t> pinned_vertices;  // point indices that never move (grid or mesh)
  bool has_pin_box = false;                    // points inside [pin_box_min, pin_box_max] never move
  glm::dvec3 pin_box_min{0.0}, pin_box_max{0.0};

  int pointCount() const;
  bool isGrid() const { return mesh == nullptr; }
  bool springEnabled(SpringType t) const {
    return t == SpringType::Structural ? enable_structural
           : t == SpringType::Shearing ? enable_shearing
                                       : enable_bending;
  }
};

struct SphereSpec {
  glm::dvec3 origin{0.0};  // m
  double radius = 0.2;     // m, > 0
  double friction = 0.3;   // [0, 1]
};

struct PlaneSpec {
  glm::dvec3 point{0.0};       // m, any point on the plane
  glm::dvec3 normal{0, 1, 0};  // unit after loading (normalised on load)
  double friction = 0.5;       // [0, 1]
};

// A static triangle mesh the cloth collides with (scene key "meshes"), read and baked into a signed
// distance field on load.
struct MeshSpec {
  std::string obj;         // as the scene wrote it
  glm::dvec3 offset{0.0};  // m, added after scaling
  double scale = 1.0;      // > 0
  double friction = 0.3;   // [0, 1], as spheres
  // m, > 0: how far the cloth's points, edges and triangles are kept from the obstacle; 0 (not given): the
  // cloth's thickness (meshThickness)
  double thickness = 0.0;
  std::shared_ptr<const MeshObstacle> mesh;
};

// A mesh obstacle's collision thickness: its own, or the cloth's.
inline double meshThickness(const ClothSpec& cloth, const MeshSpec& mesh) {
  return mesh.thickness > 0.0 ? mesh.thickness : cloth.thickness;
}

// Wind: a steady air velocity plus smooth gradient noise in space and time. The air pushes each point
// along its normal in proportion to the relative normal velocity (a simple drag model).
struct WindSpec {
  bool enabled = false;      // off unless the scene has a "wind" object
  glm::dvec3 velocity{0.0};  // m/s, steady air velocity
  double turbulence = 0.0;   // relative amplitude of the noise, 0 = steady
  double noise_scale = 1.0;  // m, spatial wavelength of the noise
  double noise_speed = 1.0;  // 1/s, how fast the noise pattern evolves
  double drag = 1.0;         // kg/m^3 * drag coefficient: force = drag * area * (v_rel . n) n
};

struct SimParams {
  double frames_per_sec = 90.0;        // frames per simulated second
  int steps_per_frame = 30;            // substeps per frame; dt = 1/(frames_per_sec*steps_per_frame)
  glm::dvec3 gravity{0.0, -9.8, 0.0};  // m/s^2
  bool self_collision = true;          // CS184 always runs it
  int stretch_passes = 1;              // Provot stretch-limit passes per substep (0 = off)
  double stretch_limit = 1.1;          // springs are shortened to at most this times rest length
  // How a stretch pass visits the springs: Gauss-Seidel over a colouring (each spring as CS184's sequential
  // Provot pass does it, springs of one colour sharing no point) or the older averaged per-point Jacobi.
  StretchScheme stretch_scheme = StretchScheme::GaussSeidel;
  // Long-range attachments (core/tethers.hpp): every free point at most stretch_limit times its rest
  // distance from its nearest pins. Off by default (CS184 has none); what holds a fine cloth from pins.
  bool tethers = false;
  Integrator integrator = Integrator::Verlet;
  int iterations = 1;  // XPBD, VBD: Gauss-Seidel sweeps (over the springs, or the points) per substep (Small Steps: 1)
  WindSpec wind;

  double dt() const { return 1.0 / (frames_per_sec * steps_per_frame); }
};

struct Scene {
  std::string path;  // file it came from, for messages
  ClothSpec cloth;
  std::vector<SphereSpec> spheres;
  std::vector<PlaneSpec> planes;
  std::vector<MeshSpec> meshes;  // collided with after the planes
  SimParams sim;
};

// One clear line: "<file>: <key>: <problem>".
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

Scene loadScene(const std::filesystem::path& file);
Scene parseScene(const std::string& json_text, const std::string& name);

// A live parameter change (Solver::setParams): everything from `cloth` and `sim` except what defines
// the topology, which stays as in `scene`: grid size, extent, orientation and pins.
void applyLiveParams(Scene& scene, const ClothSpec& cloth, const SimParams& sim);

// Limits, each a clear error instead of hours of work or gigabytes of memory (scenes/README.md).
// Largest cloth (points): its topology takes about 2 GB and a few seconds to build on the CPU (24-byte
// springs and adjacency entries, ~6 springs per point); 4096^2 took 8.5 GB.
inline constexpr long long kMaxClothPoints = 2048LL * 2048LL;
// Largest scene file: the shipped scenes are under 2 KB; a pin list of every point of the largest cloth
// is about 60 MB, which no scene needs.
inline constexpr long long kMaxSceneBytes = 16LL * 1024 * 1024;
// Substeps per frame and stretch-limit passes per substep: far beyond any stable or useful setting
// (the stiffest shipped case needs a few hundred substeps), yet each frame ends.
inline constexpr int kMaxStepsPerFrame = 10000;
inline constexpr int kMaxStretchPasses = 100;
inline constexpr int kMaxIterations = 100;  // XPBD sweeps per substep, the same reasoning
// Colliders: every point visits each one every substep, and each mesh obstacle costs its bake (0.2-0.35 s
// and a few MB for the bundled ones) before the first frame. The shipped scenes use at most 2 spheres, 1
// plane and 1 mesh; 100 copies of the table took 35 s and 453 MB to load.
inline constexpr int kMaxSpheres = 256;
inline constexpr int kMaxPlanes = 256;
inline constexpr int kMaxMeshes = 16;
// Vertices of all the obstacles' OBJ files together (the largest cloth's count): counted while each file
// is read, so a file beyond it stops being read there.
inline constexpr long long kMaxObstacleVertices = 4LL * 1024 * 1024;
// Self-collision compares each point with the points within the contact distance (2 x thickness). At rest
// a point has about pi (2 thickness)^2 / (cloth area per point) of them; beyond these bounds the pass
// compares nearly every pair (a 50 x 50 cloth with a 0.5 m thickness took 29 s a frame) or its candidate
// lists would take gigabytes (16 bytes a pair). A CS184 scene has 3 a point; refined to 512^2, about 300.
inline constexpr double kMaxSelfCollisionNeighbours = 1024;
inline constexpr double kMaxSelfCollisionPairs = double(1 << 27);

}  // namespace drape
