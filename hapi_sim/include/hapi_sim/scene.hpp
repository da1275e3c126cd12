// hapi_sim: scenes of the simulation suite behind one interface (ray
// intersection + surface radiance, ground-truth distance to the surface, the
// YAML description an evaluator reads) and the geometric primitives they are
// built from. Scene coordinates are the ground-truth world frame ("world",
// z up): what an estimator should report its poses and map in.
#pragma once
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <memory>
#include <string>
#include <vector>

#include "hapi_sim/trajectories.hpp"

namespace hapi_sim {

// One surface of the /ground_truth/scene YAML (metres):
//   sphere:   centre, radius
//   cylinder: centre, unit axis, radius, half_length (open tube |s| <= h)
//   plane:    point, unit normal, half_extent (the disc of that radius about point)
struct SurfaceSpec {
  enum Type { Sphere, Cylinder, Plane } type = Sphere;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // plane: its point
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   // plane: its normal
  double radius = 0.0, half_length = 0.0, half_extent = 0.0;
};

// The YAML schema of /ground_truth/scene and mav0/scene.yaml.
std::string sceneYaml(const std::string& name, const std::vector<SurfaceSpec>& surfaces);
// Euclidean distance from X to the bounded surface (a point's map error).
double distanceToSurface(const SurfaceSpec& s, const Eigen::Vector3d& X);
double distanceToSurfaces(const std::vector<SurfaceSpec>& s, const Eigen::Vector3d& X);
// Nearest hit t > 0 of o + t d (d unit) within the surface's bounds.
bool intersectSurface(const SurfaceSpec& s, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t);
// Unit normal of the surface at its point X, facing the side d comes from
// (n . d < 0).
Eigen::Vector3d surfaceNormal(const SurfaceSpec& s, const Eigen::Vector3d& X, const Eigen::Vector3d& d);
// The nearest hit over all the surfaces (the one Scene::trace reports) and
// the normal there, facing the ray's origin.
bool intersectSurfaces(const std::vector<SurfaceSpec>& s, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                       double* t, Eigen::Vector3d* normal);

// Bilinear grey-level texture (CV_32FC1), texel centres at integers; u wraps
// when wrap_u, otherwise both coordinates clamp.
struct Texture {
  cv::Mat texels;
  bool wrap_u = false;
  float sample(double u, double v) const;
};

class Scene {
 public:
  virtual ~Scene() = default;
  virtual std::string name() const = 0;
  virtual const std::vector<SurfaceSpec>& surfaces() const = 0;
  // How the trajectories frame this scene.
  virtual ViewGeometry view() const = 0;
  // First surface hit by the ray (scene frame, d unit): distance and radiance
  // (grey level at unit gain). False on a miss (the renderer's background).
  virtual bool trace(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t, float* grey) const = 0;
  // Where the texture came from (a file path, "generated" or "procedural").
  virtual std::string textureSource() const { return "procedural"; }
  double distance(const Eigen::Vector3d& X) const { return distanceToSurfaces(surfaces(), X); }
  std::string yaml() const { return sceneYaml(name(), surfaces()); }
};

// The textured globe of make_globe_bag (radius 0.2 m at the origin); the
// texture falls back to the generated one when the file is missing.
std::unique_ptr<Scene> makeGlobeSimScene(const std::string& texture_path);
// A forearm (cylinder r 4.5 cm, 25 cm long, axis x, resting on the table) on
// a wooden table (the plane z = 0, a disc of 0.6 m radius).
// texture_seed 0: the reference skin; another: another skin of the same kind.
std::unique_ptr<Scene> makeSkinScene(uint32_t texture_seed = 0);

// A flat skin patch (the study's stage target): the plane z = 0, a disc of
// kPatchHalfExtent about (-kPatchOffset, 0, 0), skin-textured, framed from
// 30 cm above the origin; the offset leaves room for the stage's travel
// along +x (the seen point moves to -x on the patch).
constexpr double kPatchHalfExtent = 0.4, kPatchOffset = 0.15;  // m
std::unique_ptr<Scene> makePatchScene();
// A chessboard calibration target on the plane z = 0 (scene_chessboard.cpp):
// kChessboardCols x kChessboardRows inner corners, squares of
// kChessboardSquare, framed from 50 cm.
constexpr int kChessboardCols = 8, kChessboardRows = 6;
constexpr double kChessboardSquare = 0.03;  // m
std::unique_ptr<Scene> makeChessboardScene();

// Procedural textures (one deterministic field each; texel size in metres).
cv::Mat makeSkinTexture(int width, int height, double texel, uint32_t seed = 0);
cv::Mat makeWoodTexture(int width, int height, double texel);

}  // namespace hapi_sim
