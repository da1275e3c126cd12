#include "hapi_sim/globe_sim.hpp"
#include "hapi_sim/globe_orbit.hpp"
#include "hapi_sim/motion.hpp"

#ifdef HAPI_SIM_IMAGE_FILES
#include <opencv2/imgcodecs.hpp>
#endif
#include <opencv2/imgproc.hpp>
#include <algorithm>
#include <cmath>

namespace hapi_sim {

StereoRigModel StereoRigModel::makeDefault() {
  StereoRigModel rig;
  CameraModel c;
  c.width = 640; c.height = 480;
  c.fx = 502.3; c.fy = 501.8; c.cx = 321.4; c.cy = 238.7;
  c.k1 = -0.05; c.k2 = 0.01; c.p1 = 2.0e-4; c.p2 = -1.5e-4; c.k3 = 0.0;
  rig.left = c;
  CameraModel r = c;
  r.fx = 501.6; r.fy = 501.1; r.cx = 318.9; r.cy = 240.2;
  r.k1 = -0.048; r.k2 = 0.009; r.p1 = -1.0e-4; r.p2 = 1.0e-4;
  rig.right = r;
  rig.baseline = 0.06;
  return rig;
}

Pose StereoRigModel::rightPose(const Pose& l) const {
  Pose r;
  r.q = l.q;
  r.p = l.p + l.q * Eigen::Vector3d(baseline, 0, 0);
  return r;
}

static CameraInfoData makeInfo(const CameraModel& c, double tx) {
  CameraInfoData i;
  i.width = c.width; i.height = c.height;
  i.distortion_model = "plumb_bob";
  i.D = {c.k1, c.k2, c.p1, c.p2, c.k3};
  i.K = {c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1};
  i.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  i.P = {c.fx, 0, c.cx, tx, 0, c.fy, c.cy, 0, 0, 0, 1, 0};
  return i;
}
CameraInfoData StereoRigModel::leftInfo() const { return makeInfo(left, 0.0); }
CameraInfoData StereoRigModel::rightInfo() const { return makeInfo(right, -right.fx * baseline); }

Eigen::Vector2d distortNormalized(const CameraModel& c, const Eigen::Vector2d& xn) {
  Eigen::Vector2d xd;
  distortNormalized(c, xn.x(), xn.y(), &xd.x(), &xd.y());
  return xd;
}

Eigen::Vector2d undistortNormalized(const CameraModel& c, const Eigen::Vector2d& xd) {
  // Gauss-Newton on distort(x) = xd with a numerical Jacobian; converges to
  // machine precision in a few iterations for mild distortion.
  Eigen::Vector2d x = xd;
  for (int it = 0; it < 20; ++it) {
    const Eigen::Vector2d f = distortNormalized(c, x) - xd;
    if (f.norm() < 1e-15) break;
    const double h = 1e-7;
    Eigen::Matrix2d J;
    J.col(0) = (distortNormalized(c, x + Eigen::Vector2d(h, 0)) - distortNormalized(c, x - Eigen::Vector2d(h, 0))) / (2 * h);
    J.col(1) = (distortNormalized(c, x + Eigen::Vector2d(0, h)) - distortNormalized(c, x - Eigen::Vector2d(0, h))) / (2 * h);
    x -= J.lu().solve(f);
  }
  return x;
}

Eigen::Vector3d pixelToRay(const CameraModel& c, const Eigen::Vector2d& px) {
  const Eigen::Vector2d xd((px.x() - c.cx) / c.fx, (px.y() - c.cy) / c.fy);
  const Eigen::Vector2d xn = undistortNormalized(c, xd);
  return Eigen::Vector3d(xn.x(), xn.y(), 1.0).normalized();
}

// ---------------------------------------------------------------- scene
cv::Mat GlobeScene::generateTexture(int width, int height, uint32_t seed) {
  // Continents-like pattern: sum of seeded random waves on the sphere plus
  // seeded blobs; only integer outputs of mt19937 are used (portable).
  std::mt19937 rng(seed);
  auto uni = [&rng]() { return (static_cast<double>(rng()) + 0.5) / 4294967296.0; };
  struct Wave { Eigen::Vector3d k; double ph, a; };
  std::vector<Wave> waves;
  for (int i = 0; i < 24; ++i) {
    Eigen::Vector3d k(uni() - 0.5, uni() - 0.5, uni() - 0.5);
    k = k.normalized() * (2.0 + 28.0 * uni());
    waves.push_back({k, 2 * M_PI * uni(), 1.0 / (1.0 + 0.1 * k.norm())});
  }
  cv::Mat tex(height, width, CV_32FC1);
  for (int r = 0; r < height; ++r) {
    const double lat = M_PI / 2 - (r + 0.5) * M_PI / height;
    for (int cidx = 0; cidx < width; ++cidx) {
      const double lon = -M_PI + (cidx + 0.5) * 2 * M_PI / width;
      const Eigen::Vector3d n(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat));
      double s = 0;
      for (const auto& w : waves) s += w.a * std::sin(w.k.dot(n) + w.ph);
      tex.at<float>(r, cidx) = static_cast<float>(std::clamp(128.0 + 45.0 * s, 5.0, 250.0));
    }
  }
  return tex;
}

GlobeScene GlobeScene::makeDefault(const std::string& path, double radius, const Eigen::Vector3d& centre) {
  GlobeScene s;
  s.radius = radius;
  s.centre = centre;
  cv::Mat img;
#ifdef HAPI_SIM_IMAGE_FILES
  if (!path.empty()) img = cv::imread(path, cv::IMREAD_GRAYSCALE);
#endif
  // Without image files (no imgcodecs) a texture file is as absent as a
  // missing one: texture_source then says "generated".
  if (!img.empty()) {
    img.convertTo(s.texture, CV_32FC1);
    // Boost contrast: oceans are very dark in the xplanet map.
    cv::Mat lifted = s.texture * 0.8 + 30.0;
    s.texture = lifted;
    s.texture_source = path;
  } else {
    s.texture = generateTexture();
    s.texture_source = "generated";
  }
  return s;
}

Eigen::Vector3d GlobeScene::pointFromLatLon(double lat, double lon) const {
  return centre + radius * Eigen::Vector3d(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat));
}

void GlobeScene::latLonFromPoint(const Eigen::Vector3d& X, double* lat, double* lon) const {
  const Eigen::Vector3d n = (X - centre).normalized();
  *lat = std::asin(std::clamp(n.z(), -1.0, 1.0));
  *lon = std::atan2(n.y(), n.x());
}

Eigen::Vector2d GlobeScene::texelFromLatLon(double lat, double lon) const {
  return {(lon + M_PI) / (2 * M_PI) * texture.cols - 0.5, (M_PI / 2 - lat) / M_PI * texture.rows - 0.5};
}

float GlobeScene::sample(double lat, double lon) const {
  const Eigen::Vector2d uv = texelFromLatLon(lat, lon);
  const int W = texture.cols, H = texture.rows;
  const double fu = std::floor(uv.x()), fv = std::floor(uv.y());
  const float au = static_cast<float>(uv.x() - fu), av = static_cast<float>(uv.y() - fv);
  int u0 = static_cast<int>(fu), v0 = static_cast<int>(fv);
  int u1 = u0 + 1, v1 = v0 + 1;
  u0 = ((u0 % W) + W) % W; u1 = ((u1 % W) + W) % W;
  v0 = std::clamp(v0, 0, H - 1); v1 = std::clamp(v1, 0, H - 1);
  const float* r0 = texture.ptr<float>(v0);
  const float* r1 = texture.ptr<float>(v1);
  return (1 - av) * ((1 - au) * r0[u0] + au * r0[u1]) + av * ((1 - au) * r1[u0] + au * r1[u1]);
}

bool GlobeScene::intersect(const Eigen::Vector3d& o, const Eigen::Vector3d& d, Eigen::Vector3d* hit) const {
  const Eigen::Vector3d oc = o - centre;
  const double b = oc.dot(d);
  const double c = oc.squaredNorm() - radius * radius;
  const double disc = b * b - c;
  if (disc < 0) return false;
  const double sq = std::sqrt(disc);
  double t = -b - sq;
  if (t <= 0) t = -b + sq;
  if (t <= 0) return false;
  if (hit) *hit = o + t * d;
  return true;
}

bool project(const Eigen::Vector3d& X_w, const Pose& T_wc, const CameraModel& c, Eigen::Vector2d* px) {
  const Eigen::Vector3d Xc = T_wc.q.conjugate() * (X_w - T_wc.p);
  if (Xc.z() <= 1e-9) return false;
  const Eigen::Vector2d xd = distortNormalized(c, Eigen::Vector2d(Xc.x() / Xc.z(), Xc.y() / Xc.z()));
  *px = Eigen::Vector2d(c.fx * xd.x() + c.cx, c.fy * xd.y() + c.cy);
  return true;
}

bool castRay(const Eigen::Vector2d& px, const Pose& T_wc, const CameraModel& c, const GlobeScene& s,
             Eigen::Vector3d* X_w) {
  const Eigen::Vector3d d = T_wc.q * pixelToRay(c, px);
  return s.intersect(T_wc.p, d, X_w);
}

bool isVisible(const Eigen::Vector3d& X_w, const Pose& T_wc, const GlobeScene& s) {
  return (X_w - s.centre).dot(T_wc.p - X_w) > 0;
}

// ---------------------------------------------------------------- trajectory
// The orbit is written once (globe_orbit.hpp); its derivatives are exact (Jet2).
namespace {
template <class T>
PoseT<T> orbitPose(GlobePath orbit, const T& t, const Eigen::Vector3d& centre, double radius) {
  const V3<T> c(centre);
  return orbit == GlobePath::kSpiral ? globeSpiralPose(t, c, radius) : globeOrbitPose(t, c, radius);
}
}  // namespace

Pose Trajectory::pose(double t) const {
  const PoseT<double> P = orbitPose(orbit_, t, centre_, radius_);
  Eigen::Matrix3d R;
  R.col(0) = Eigen::Vector3d(P.R.c0.x, P.R.c0.y, P.R.c0.z);
  R.col(1) = Eigen::Vector3d(P.R.c1.x, P.R.c1.y, P.R.c1.z);
  R.col(2) = Eigen::Vector3d(P.R.c2.x, P.R.c2.y, P.R.c2.z);
  Pose out;
  out.q = Eigen::Quaterniond(R).normalized();
  out.p = Eigen::Vector3d(P.p.x, P.p.y, P.p.z);
  return out;
}

TrajectorySample Trajectory::at(double t) const {
  const MotionSample m = motionFromJets(t, orbitPose(orbit_, Jet2::time(t), centre_, radius_));
  TrajectorySample s;
  s.t = t;
  s.T_wc = pose(t);
  s.v_w = m.v;
  s.a_w = m.a;
  s.omega_c = m.omega;
  return s;
}

// ---------------------------------------------------------------- noise
double GaussianRng::uniform01() { return (static_cast<double>(rng_()) + 0.5) / 4294967296.0; }

double GaussianRng::normal() {
  if (has_spare_) { has_spare_ = false; return spare_; }
  const double u1 = uniform01(), u2 = uniform01();
  const double r = std::sqrt(-2.0 * std::log(u1));
  spare_ = r * std::sin(2 * M_PI * u2);
  has_spare_ = true;
  return r * std::cos(2 * M_PI * u2);
}

uint32_t mixSeed(uint32_t seed, uint32_t frame, uint32_t camera) {
  uint64_t z = (static_cast<uint64_t>(seed) << 32) ^ (static_cast<uint64_t>(frame) << 2) ^ camera;
  z += 0x9E3779B97F4A7C15ull;  // splitmix64 finaliser
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<uint32_t>(z ^ (z >> 32));
}

// ---------------------------------------------------------------- renderer
Renderer::Renderer(const GlobeScene& scene, const CameraModel& cam, int supersample)
    : scene_(scene), cam_(cam), ss_(std::max(1, supersample)) {
  const int W = cam.width * ss_, H = cam.height * ss_;
  rays_.resize(static_cast<size_t>(W) * H);
  for (int r = 0; r < H; ++r)
    for (int c = 0; c < W; ++c) {
      // Sub-pixel centres, e.g. ss=2: offsets -0.25, +0.25.
      const Eigen::Vector2d px((c + 0.5) / ss_ - 0.5, (r + 0.5) / ss_ - 0.5);
      rays_[static_cast<size_t>(r) * W + c] = pixelToRay(cam, px).cast<float>();
    }
}

float Renderer::background(int u, int v) {
  // Dark, smooth, low texture: gentle gradient plus a faint long-period ripple.
  return 18.0f + 6.0f * static_cast<float>(v) / 480.0f +
         2.0f * static_cast<float>(std::sin(0.013 * u) * std::cos(0.017 * v));
}

cv::Mat Renderer::renderFloat(const Pose& T_wc) const {
  const int W = cam_.width, H = cam_.height, SW = W * ss_;
  cv::Mat out(H, W, CV_32FC1);
  const Eigen::Matrix3d R = T_wc.q.toRotationMatrix();
  const Eigen::Vector3d oc = T_wc.p - scene_.centre;
  const double c0 = oc.squaredNorm() - scene_.radius * scene_.radius;
  const float inv = 1.0f / static_cast<float>(ss_ * ss_);
  for (int v = 0; v < H; ++v) {
    float* row = out.ptr<float>(v);
    for (int u = 0; u < W; ++u) {
      float acc = 0.f;
      for (int sy = 0; sy < ss_; ++sy)
        for (int sx = 0; sx < ss_; ++sx) {
          const Eigen::Vector3d d = R * rays_[static_cast<size_t>(v * ss_ + sy) * SW + (u * ss_ + sx)].cast<double>();
          const double b = oc.dot(d);
          const double disc = b * b - c0;
          double t = -1;
          if (disc >= 0) {
            const double sq = std::sqrt(disc);
            t = -b - sq;
            if (t <= 0) t = -b + sq;
          }
          if (t > 0) {
            const Eigen::Vector3d n = oc + t * d;  // relative to centre
            const double lat = std::asin(std::clamp(n.z() / scene_.radius, -1.0, 1.0));
            const double lon = std::atan2(n.y(), n.x());
            acc += scene_.sample(lat, lon);
          } else {
            acc += background(u, v);
          }
        }
      row[u] = acc * inv;
    }
  }
  return out;
}

cv::Mat Renderer::render(const Pose& T_wc, uint32_t seed, double noise_sigma) const {
  const cv::Mat f = renderFloat(T_wc);
  cv::Mat out(f.rows, f.cols, CV_8UC1);
  GaussianRng rng(seed);
  for (int v = 0; v < f.rows; ++v) {
    const float* fr = f.ptr<float>(v);
    uint8_t* orow = out.ptr<uint8_t>(v);
    for (int u = 0; u < f.cols; ++u) {
      double val = fr[u];
      if (noise_sigma > 0) val += noise_sigma * rng.normal();
      orow[u] = static_cast<uint8_t>(std::clamp(std::lround(val), 0L, 255L));
    }
  }
  return out;
}

}  // namespace hapi_sim
