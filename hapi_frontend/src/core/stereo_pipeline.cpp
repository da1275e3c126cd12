// StereoPipeline: grey/downscale -> detect L/R -> undistort keypoints ->
// F from the rig -> match -> N strongest -> two-step MMSE -> depth gate ->
// colour (docs/DESIGN.md "Front end"). Bad images give a reason string, never an
// exception.
#include "hapi_frontend/stereo_pipeline.hpp"

#include "hapi_frontend/image_quality.hpp"

#include "hapi_frontend/cpu_stereo_matcher.hpp"
#include "hapi_frontend/mmse_triangulator.hpp"
#include "hapi_frontend/opencv_extractors.hpp"
#include "hapi_frontend/orb_extractor.hpp"
#include "hapi_frontend/stereo_refine.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numeric>
#include <optional>
#include <stdexcept>

namespace hapi_frontend {

struct StereoPipeline::Impl {
  PipelineParams p;
  std::unique_ptr<FeatureExtractor> extractor;
  std::unique_ptr<StereoMatcher> matcher;
  std::string matcher_status;
  bool calibrated = false;
  CameraCalib calib_l, calib_r;
  std::optional<CameraModel> cam_l, cam_r;
  StereoRig rig;
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
  std::optional<MmseTriangulator> mmse;
  cv::Mat small_l, small_r, grey_l, grey_r;
};

StereoPipeline::StereoPipeline(const PipelineParams& params) : impl_(new Impl) {
  const std::string err = params.validate();
  if (!err.empty()) throw std::invalid_argument("StereoPipeline: " + err);
  impl_->p = params;
  if (params.detector == "orb") {
    OrbParams op;
    op.n_features = params.detector_features;
    op.n_levels = params.pyramid_levels;
    op.fast_threshold = params.fast_threshold;
    impl_->extractor = std::make_unique<OrbExtractor>(op, params.use_gpu);
  } else {
    impl_->extractor = std::make_unique<AkazeExtractor>();
  }
  // The GPU matcher only pays off next to the GPU ORB (descriptors already
  // produced there); AKAZE always matches on the CPU.
  impl_->matcher = makeStereoMatcher(params.use_gpu && params.detector == "orb", &impl_->matcher_status);
}

StereoPipeline::~StereoPipeline() = default;

const PipelineParams& StereoPipeline::params() const { return impl_->p; }
const StereoRig& StereoPipeline::rig() const { return impl_->rig; }
bool StereoPipeline::hasCalibration() const { return impl_->calibrated; }

std::string StereoPipeline::setCalibration(const CameraCalib& left, const CameraCalib& right) {
  Impl& m = *impl_;
  m.calibrated = false;
  std::string e = left.validate();
  if (!e.empty()) return "left calibration: " + e;
  e = right.validate();
  if (!e.empty()) return "right calibration: " + e;
  if (left.width != right.width || left.height != right.height) return "left and right image sizes differ";
  const double B = -right.P[3] / right.P[0];
  if (!(std::abs(B) > 1e-6) || !std::isfinite(B))
    return "right P[3] gives no baseline (P[0,3] must be -fx * baseline)";
  m.calib_l = left;
  m.calib_r = right;
  m.cam_l.emplace(left, m.p.rectified_input);
  m.cam_r.emplace(right, m.p.rectified_input);
  m.rig = StereoRig::fromCalib(left, right, m.p.rectified_input);
  m.F = m.rig.fundamental(m.cam_l->K(), m.cam_r->K());
  // F is defined up to scale and the epipolar test is scale-invariant; unit
  // norm only keeps the numbers in a comfortable range.
  const double fn = m.F.norm();
  if (!(fn > 0) || !m.F.allFinite()) return "degenerate stereo geometry (fundamental matrix is zero)";
  m.F /= fn;
  m.mmse.emplace(m.cam_l->K(), m.cam_r->K(), m.rig, m.p.pixel_sigma);
  m.calibrated = true;
  return "";
}

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Any supported input to CV_8UC1: 8-bit grey as is, BGR(A) converted,
// 16-bit grey scaled by 1/256 (mono16 keeps its 8 most significant bits).
std::string toGrey(const cv::Mat& in, cv::Mat* out) {
  switch (in.type()) {
    case CV_8UC1: *out = in; return "";
    case CV_8UC3: cv::cvtColor(in, *out, cv::COLOR_BGR2GRAY); return "";
    case CV_8UC4: cv::cvtColor(in, *out, cv::COLOR_BGRA2GRAY); return "";
    case CV_16UC1: in.convertTo(*out, CV_8U, 1.0 / 256.0); return "";
    default: return "unsupported image type " + std::to_string(in.type()) + " (need 8UC1, 8UC3, 8UC4 or 16UC1)";
  }
}
}  // namespace

std::string StereoPipeline::process(const cv::Mat& left_in, const cv::Mat& right_in, const cv::Mat& left_colour,
                                    StereoFrameResult* out) {
  if (out == nullptr) return "null output";
  *out = StereoFrameResult();
  Impl& m = *impl_;
  const PipelineParams& p = m.p;
  if (!m.calibrated) return "no valid calibration";
  if (left_in.empty() || right_in.empty()) return "empty image";
  if (left_in.size() != right_in.size()) return "left and right images differ in size";
  if (left_in.cols != m.calib_l.width || left_in.rows != m.calib_l.height)
    return "image size " + std::to_string(left_in.cols) + "x" + std::to_string(left_in.rows) +
           " differs from the calibrated " + std::to_string(m.calib_l.width) + "x" + std::to_string(m.calib_l.height);
  if (!left_colour.empty() && (left_colour.size() != left_in.size() || left_colour.type() != CV_8UC3))
    return "left colour image must be CV_8UC3 of the grey image's size";
  try {
    const auto t_all = Clock::now();
    // --- convert (+ downscale)
    auto t0 = Clock::now();
    std::string e = toGrey(left_in, &m.grey_l);
    if (e.empty()) e = toGrey(right_in, &m.grey_r);
    if (!e.empty()) return e;
    const double ds = p.downscale;
    cv::Mat det_l = m.grey_l, det_r = m.grey_r;
    if (ds > 1.0) {
      const cv::Size sz(std::max(1, static_cast<int>(std::lround(left_in.cols / ds))),
                        std::max(1, static_cast<int>(std::lround(left_in.rows / ds))));
      cv::resize(m.grey_l, m.small_l, sz, 0, 0, cv::INTER_AREA);
      cv::resize(m.grey_r, m.small_r, sz, 0, 0, cv::INTER_AREA);
      det_l = m.small_l;
      det_r = m.small_r;
    }
    out->times.convert = msSince(t0);
    // --- detect
    t0 = Clock::now();
    FeatureSet fl = m.extractor->extract(det_l);
    out->times.detect_left = msSince(t0);
    t0 = Clock::now();
    FeatureSet fr = m.extractor->extract(det_r);
    out->times.detect_right = msSince(t0);
    // Asked after extract(): a CUDA failure during it switches to the CPU.
    out->used_gpu = m.extractor->usingGpu();
    out->descriptor_type = fl.type;
    out->n_left = static_cast<int>(fl.keypoints.size());
    out->n_right = static_cast<int>(fr.keypoints.size());
    // --- undistort (full-resolution pixels; pixel centres at integers, so a
    // downscaled coordinate x maps to (x + 0.5) * ds - 0.5)
    t0 = Clock::now();
    auto fullRes = [ds](const FeatureSet& fs) {
      std::vector<cv::Point2f> px(fs.keypoints.size());
      for (size_t i = 0; i < px.size(); ++i) {
        px[i].x = static_cast<float>((fs.keypoints[i].x + 0.5) * ds - 0.5);
        px[i].y = static_cast<float>((fs.keypoints[i].y + 0.5) * ds - 0.5);
      }
      return px;
    };
    const std::vector<cv::Point2f> raw_l = fullRes(fl), raw_r = fullRes(fr);
    const std::vector<Eigen::Vector2d> und_l = m.cam_l->undistort(raw_l), und_r = m.cam_r->undistort(raw_r);
    out->times.undistort = msSince(t0);
    // --- match
    t0 = Clock::now();
    std::vector<StereoMatch> matches = m.matcher->match(fl, und_l, fr, und_r, m.F, p.match);
    out->times.match = msSince(t0);
    out->used_gpu = out->used_gpu || m.matcher->usingGpu();
    out->n_matches = static_cast<int>(matches.size());
    // --- N strongest + triangulate. Strength = left response; ties keep the
    // matcher's order (left index ascending), so the result is deterministic.
    t0 = Clock::now();
    std::stable_sort(matches.begin(), matches.end(), [&](const StereoMatch& a, const StereoMatch& b) {
      return fl.keypoints[a.left].response > fl.keypoints[b.left].response;
    });
    const int bytes = fl.descriptors.cols;
    RefineParams rp;
    rp.half_patch = p.refine_half_patch;
    rp.radius = p.refine_radius;
    rp.min_zncc = p.refine_min_zncc;
    double refine_ms = 0.0;
    std::vector<int> kept_left;
    for (const StereoMatch& mt : matches) {
      if (static_cast<int>(out->landmarks.size()) >= p.landmarks_per_frame) break;
      const Feature& kl = fl.keypoints[mt.left];
      const Feature& kr = fr.keypoints[mt.right];
      Eigen::Vector2d ur = und_r[mt.right];
      // Noise model. Unrefined: keypoints are quantised to their pyramid
      // level's grid, so sigma = pixel_sigma * level scale * downscale.
      // Refined: the right pixel is aligned to the left patch at full
      // resolution, so both carry the same level-0 noise pixel_sigma.
      double sl = p.pixel_sigma * ds * (p.detector == "orb" ? kl.size / 31.0 : 1.0);
      double sr = p.pixel_sigma * ds * (p.detector == "orb" ? kr.size / 31.0 : 1.0);
      if (p.refine_subpixel) {
        const auto tr = Clock::now();
        const RefineResult rr = refineStereoMatch(m.grey_l, m.grey_r, raw_l[mt.left], raw_r[mt.right], rp);
        if (rr.ok) ur = m.cam_r->undistort({rr.right})[0];
        refine_ms += msSince(tr);
        if (!rr.ok) {
          ++out->n_refine_rejected;
          continue;
        }
        sl = sr = p.pixel_sigma;
      }
      const MmseEstimate est = m.mmse->estimate(und_l[mt.left], ur, sl, sr);
      if (!est.valid) continue;
      const double z = est.position.z();
      if (z < p.min_depth || z > p.max_depth) continue;
      StereoLandmarkOut lm;
      lm.uv_left = und_l[mt.left];
      lm.uv_right = ur;
      lm.position = est.position;
      lm.covariance = est.covariance;
      lm.response = kl.response;
      lm.hamming = mt.distance;
      const int u = std::min(std::max(static_cast<int>(std::lround(raw_l[mt.left].x)), 0), left_in.cols - 1);
      const int v = std::min(std::max(static_cast<int>(std::lround(raw_l[mt.left].y)), 0), left_in.rows - 1);
      if (!left_colour.empty()) {
        const cv::Vec3b c = left_colour.at<cv::Vec3b>(v, u);  // BGR
        lm.rgb = {{c[2], c[1], c[0]}};
      } else {
        const uint8_t g = m.grey_l.at<uint8_t>(v, u);
        lm.rgb = {{g, g, g}};
      }
      out->landmarks.push_back(lm);
      kept_left.push_back(mt.left);
    }
    out->descriptors.create(static_cast<int>(kept_left.size()), bytes, CV_8U);
    for (size_t i = 0; i < kept_left.size(); ++i)
      std::memcpy(out->descriptors.ptr(static_cast<int>(i)), fl.descriptors.ptr(kept_left[i]), bytes);
    out->times.refine = refine_ms;
    out->times.triangulate = msSince(t0) - refine_ms;
    std::vector<double> offsets;
    offsets.reserve(out->landmarks.size());
    for (const StereoLandmarkOut& lm : out->landmarks) offsets.push_back(epipolarOffset(m.F, lm.uv_left, lm.uv_right));
    out->vertical_disparity_px = median(std::move(offsets));
    out->motion_blur = motionBlur(m.grey_l);
    out->times.total = msSince(t_all);
  } catch (const std::exception& ex) {
    // OpenCV may throw on pathological input (e.g. a corrupt Mat header); the
    // frame is dropped with the reason instead of crashing the nodelet.
    *out = StereoFrameResult();
    return std::string("front end failed on this frame: ") + ex.what();
  }
  return "";
}

std::string publishProblem(const StereoFrameResult& res) {
  const size_t n = res.landmarks.size();
  const cv::Mat& d = res.descriptors;
  if (n > 0 && (d.rows != static_cast<int>(n) || d.type() != CV_8UC1 || d.cols <= 0))
    return "descriptor matrix " + std::to_string(d.rows) + "x" + std::to_string(d.cols) + " does not match " +
           std::to_string(n) + " landmarks";
  for (size_t i = 0; i < n; ++i) {
    const StereoLandmarkOut& in = res.landmarks[i];
    if (!in.position.allFinite() || !in.covariance.allFinite() || !in.uv_left.allFinite() || !in.uv_right.allFinite())
      return "landmark " + std::to_string(i) + " has non-finite values";
  }
  return "";
}

}  // namespace hapi_frontend
