// The globe scene of the suite: make_globe_bag's textured sphere behind the
// Scene interface (framed from 0.55 m, the legacy orbit as its smooth case).
#include <cmath>

#include "hapi_sim/scene.hpp"

namespace hapi_sim {
namespace {

class GlobeSimScene : public Scene {
 public:
  explicit GlobeSimScene(const std::string& texture) : globe_(GlobeScene::makeDefault(texture)) {
    SurfaceSpec s;
    s.type = SurfaceSpec::Sphere;
    s.centre = globe_.centre;
    s.radius = globe_.radius;
    surfaces_.push_back(s);
  }
  std::string name() const override { return "globe"; }
  std::string textureSource() const override { return globe_.texture_source; }
  const std::vector<SurfaceSpec>& surfaces() const override { return surfaces_; }
  ViewGeometry view() const override {
    ViewGeometry v;
    v.centre = globe_.centre;
    v.along = Eigen::Vector3d::UnitX();
    v.up = Eigen::Vector3d::UnitZ();  // camera on the -y side at rest, as the legacy orbit starts
    v.standoff = 0.55;
    v.extent = 0.1;
    v.globe = true;
    v.globe_radius = globe_.radius;
    return v;
  }
  bool trace(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t, float* grey) const override {
    if (!intersectSurface(surfaces_[0], o, d, t)) return false;
    double lat, lon;
    globe_.latLonFromPoint(o + *t * d, &lat, &lon);
    *grey = globe_.sample(lat, lon);
    return true;
  }

 private:
  GlobeScene globe_;
  std::vector<SurfaceSpec> surfaces_;
};

}  // namespace

std::unique_ptr<Scene> makeGlobeSimScene(const std::string& texture_path) {
  return std::make_unique<GlobeSimScene>(texture_path);
}

}  // namespace hapi_sim
