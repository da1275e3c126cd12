// The skin scene: a forearm-sized cylinder (radius 4.5 cm, 25 cm long, axis
// along x) resting on a wooden table (z = 0), framed from 22 cm above the
// skin. Skin texel 0.2 mm, wood texel 0.6 mm: finer than a pixel at the
// working distances (0.4-0.8 mm per pixel at 20-40 cm, f ~ 500 px). A fixed
// light from above-left gives the arm a gentle Lambertian shading.
#include <algorithm>
#include <cmath>

#include "hapi_sim/scene.hpp"

namespace hapi_sim {
namespace {

constexpr double kArmRadius = 0.045, kArmHalfLength = 0.125, kTableHalfExtent = 0.6;
constexpr double kSkinTexel = 0.2e-3, kWoodTexel = 0.6e-3;

class SkinScene : public Scene {
 public:
  explicit SkinScene(uint32_t texture_seed) {
    SurfaceSpec arm;
    arm.type = SurfaceSpec::Cylinder;
    arm.centre = Eigen::Vector3d(0, 0, kArmRadius);
    arm.axis = Eigen::Vector3d::UnitX();
    arm.radius = kArmRadius;
    arm.half_length = kArmHalfLength;
    SurfaceSpec table;
    table.type = SurfaceSpec::Plane;
    table.centre = Eigen::Vector3d::Zero();
    table.axis = Eigen::Vector3d::UnitZ();
    table.half_extent = kTableHalfExtent;
    surfaces_ = {arm, table};
    skin_.texels = makeSkinTexture(static_cast<int>(std::lround(2 * M_PI * kArmRadius / kSkinTexel)),
                                   static_cast<int>(std::lround(2 * kArmHalfLength / kSkinTexel)), kSkinTexel,
                                   texture_seed);
    skin_.wrap_u = true;
    const int n = static_cast<int>(std::lround(2 * kTableHalfExtent / kWoodTexel));
    wood_.texels = makeWoodTexture(n, n, kWoodTexel);
    light_ = Eigen::Vector3d(0.3, -0.4, 1.0).normalized();
  }
  std::string name() const override { return "skin"; }
  const std::vector<SurfaceSpec>& surfaces() const override { return surfaces_; }
  ViewGeometry view() const override {
    ViewGeometry v;
    v.centre = Eigen::Vector3d(0, 0, 2 * kArmRadius);  // top of the arm
    v.along = Eigen::Vector3d::UnitX();                // the arm runs across the image
    v.up = Eigen::Vector3d::UnitY();
    v.standoff = 0.22;
    v.extent = 0.08;
    return v;
  }
  bool trace(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t, float* grey) const override {
    double ta = 0, tt = 0;
    const bool arm = intersectSurface(surfaces_[0], o, d, &ta);
    const bool table = intersectSurface(surfaces_[1], o, d, &tt);
    if (arm && (!table || ta <= tt)) {
      const Eigen::Vector3d X = o + ta * d - surfaces_[0].centre;  // axis = x
      const double theta = std::atan2(X.z(), X.y());
      const double u = (theta + M_PI) / (2 * M_PI) * skin_.texels.cols - 0.5;
      const double v = (X.x() + kArmHalfLength) / kSkinTexel - 0.5;
      Eigen::Vector3d n(0, X.y(), X.z());
      n /= kArmRadius;
      const double facing = n.dot(d) < 0 ? std::max(0.0, n.dot(light_)) : 0.0;  // inside of the tube: unlit
      *grey = static_cast<float>(skin_.sample(u, v) * (0.72 + 0.28 * facing));
      *t = ta;
      return true;
    }
    if (table) {
      const Eigen::Vector3d X = o + tt * d;
      *grey = 0.9f * wood_.sample((X.x() + kTableHalfExtent) / kWoodTexel - 0.5, (X.y() + kTableHalfExtent) / kWoodTexel - 0.5);
      *t = tt;
      return true;
    }
    return false;
  }

 private:
  std::vector<SurfaceSpec> surfaces_;
  Texture skin_, wood_;
  Eigen::Vector3d light_;
};

}  // namespace

std::unique_ptr<Scene> makeSkinScene(uint32_t texture_seed) { return std::make_unique<SkinScene>(texture_seed); }

}  // namespace hapi_sim
