// The patch scene: a flat piece of skin (the skin texture on the plane
// z = 0) under even light, framed from 30 cm, the distance of the study's
// stage runs. At 30 cm a pixel covers 0.6 mm (f ~ 500 px); the 0.3 mm texel
// keeps the 2 x 2 anti-aliasing's sub-pixels on texels of their own. The
// view at 30 cm spans 38 x 29 cm: the disc (radius kPatchHalfExtent, centre
// kPatchOffset behind the view centre along x) fills it while the seen point
// moves from +0.15 to -0.17 m along x (the lens widens the corners): 32 cm of
// stage travel.
#include <cmath>

#include "hapi_sim/scene.hpp"

namespace hapi_sim {
namespace {

constexpr double kPatchTexel = 0.3e-3;

class PatchScene : public Scene {
 public:
  PatchScene() {
    SurfaceSpec patch;
    patch.type = SurfaceSpec::Plane;
    patch.centre = Eigen::Vector3d(-kPatchOffset, 0, 0);
    patch.axis = Eigen::Vector3d::UnitZ();
    patch.half_extent = kPatchHalfExtent;
    surfaces_ = {patch};
    const int n = static_cast<int>(std::lround(2 * kPatchHalfExtent / kPatchTexel));
    skin_.texels = makeSkinTexture(n, n, kPatchTexel);
  }
  std::string name() const override { return "patch"; }
  const std::vector<SurfaceSpec>& surfaces() const override { return surfaces_; }
  ViewGeometry view() const override {
    ViewGeometry v;
    v.centre = Eigen::Vector3d::Zero();
    v.along = Eigen::Vector3d::UnitX();  // the stage's direction runs across the image
    v.up = Eigen::Vector3d::UnitY();
    v.standoff = 0.30;
    v.extent = 0.08;
    return v;
  }
  bool trace(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t, float* grey) const override {
    if (!intersectSurface(surfaces_[0], o, d, t)) return false;
    const Eigen::Vector3d X = o + *t * d - surfaces_[0].centre;
    *grey = skin_.sample((X.x() + kPatchHalfExtent) / kPatchTexel - 0.5, (X.y() + kPatchHalfExtent) / kPatchTexel - 0.5);
    return true;
  }

 private:
  std::vector<SurfaceSpec> surfaces_;
  Texture skin_;
};

}  // namespace

std::unique_ptr<Scene> makePatchScene() { return std::make_unique<PatchScene>(); }

}  // namespace hapi_sim
