#include "frontend_params.hpp"

#include <ros/param.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hapi_frontend {
namespace {

// Typed reads through XmlRpcValue: ros::NodeHandle::param() silently returns
// the default when the stored type differs (e.g. "max_landmarks: 2e2" or a
// quoted number), which hides configuration mistakes.
class Reader {
 public:
  Reader(const ros::NodeHandle& nh, ParamLoadResult* res) : nh_(nh), res_(res) {}

  void read(const std::string& name, bool* v) {
    XmlRpc::XmlRpcValue x;
    if (!fetch(name, &x)) return;
    if (x.getType() == XmlRpc::XmlRpcValue::TypeBoolean) *v = static_cast<bool>(x);
    else typeError(name, "a bool (true/false)", x);
  }
  void read(const std::string& name, int* v) {
    XmlRpc::XmlRpcValue x;
    if (!fetch(name, &x)) return;
    if (x.getType() == XmlRpc::XmlRpcValue::TypeInt) *v = static_cast<int>(x);
    else typeError(name, "an integer", x);
  }
  void read(const std::string& name, double* v) {
    XmlRpc::XmlRpcValue x;
    if (!fetch(name, &x)) return;
    // An integer literal ("max_depth: 20") is a valid real number.
    if (x.getType() == XmlRpc::XmlRpcValue::TypeDouble) *v = static_cast<double>(x);
    else if (x.getType() == XmlRpc::XmlRpcValue::TypeInt) *v = static_cast<int>(x);
    else typeError(name, "a number", x);
  }
  void read(const std::string& name, std::string* v) {
    XmlRpc::XmlRpcValue x;
    if (!fetch(name, &x)) return;
    if (x.getType() == XmlRpc::XmlRpcValue::TypeString) *v = static_cast<std::string>(x);
    else typeError(name, "a string", x);
  }

 private:
  bool fetch(const std::string& name, XmlRpc::XmlRpcValue* x) {
    return nh_.hasParam(name) && nh_.getParam(name, *x);
  }
  void typeError(const std::string& name, const char* expected, XmlRpc::XmlRpcValue& x) {
    std::ostringstream os;
    os << "~" << name << " must be " << expected << ", got '" << x.toXml() << "'";
    res_->errors.push_back(os.str());
  }
  const ros::NodeHandle& nh_;
  ParamLoadResult* res_;
};

void require(bool ok, const std::string& what, ParamLoadResult* res) {
  if (!ok) res->errors.push_back(what);
}

}  // namespace

const std::vector<std::string>& frontendParamNames() {
  static const std::vector<std::string> names = {
      "detector", "use_gpu", "max_landmarks", "detector_features", "fast_threshold", "pyramid_levels",
      "downscale", "rectified_input", "pixel_sigma", "min_depth", "max_depth", "max_epipolar_px",
      "min_disparity", "max_disparity", "match_ratio", "match_max_hamming", "match_cross_check",
      "approximate_sync", "queue_size", "approx_slop", "image_transport", "mono16_bits", "max_backwards_jump"};
  return names;
}

ParamLoadResult loadFrontendParams(const ros::NodeHandle& nh, FrontendNodeletParams* p) {
  ParamLoadResult res;
  Reader r(nh, &res);
  PipelineParams& pp = p->pipeline;
  r.read("detector", &pp.detector);
  r.read("use_gpu", &pp.use_gpu);
  r.read("max_landmarks", &pp.max_landmarks);
  r.read("detector_features", &pp.detector_features);
  r.read("fast_threshold", &pp.fast_threshold);
  r.read("pyramid_levels", &pp.pyramid_levels);
  r.read("downscale", &pp.downscale);
  r.read("rectified_input", &pp.rectified_input);
  r.read("pixel_sigma", &pp.pixel_sigma);
  r.read("min_depth", &pp.min_depth);
  r.read("max_depth", &pp.max_depth);
  r.read("max_epipolar_px", &pp.match.max_epipolar_px);
  r.read("min_disparity", &pp.match.min_disparity);
  r.read("max_disparity", &pp.match.max_disparity);
  r.read("match_ratio", &pp.match.ratio);
  r.read("match_max_hamming", &pp.match.max_hamming);
  r.read("match_cross_check", &pp.match.cross_check);
  r.read("approximate_sync", &p->approximate_sync);
  r.read("queue_size", &p->queue_size);
  r.read("approx_slop", &p->approx_slop);
  r.read("image_transport", &p->image_transport);
  r.read("mono16_bits", &p->mono16_bits);
  r.read("max_backwards_jump", &p->max_backwards_jump);

  // Our own checks first, with the parameter names a user sees; the core's
  // validate() then checks the pipeline fields once more (single source of
  // truth for ranges the core depends on).
  require(pp.detector == "orb" || pp.detector == "akaze", "~detector must be 'orb' or 'akaze', got '" + pp.detector + "'", &res);
  require(pp.max_landmarks >= 1, "~max_landmarks must be >= 1", &res);
  require(pp.detector_features >= pp.max_landmarks, "~detector_features must be >= ~max_landmarks", &res);
  require(pp.fast_threshold >= 1 && pp.fast_threshold <= 254, "~fast_threshold must be in [1, 254]", &res);
  require(pp.pyramid_levels >= 1 && pp.pyramid_levels <= 16, "~pyramid_levels must be in [1, 16]", &res);
  require(std::isfinite(pp.downscale) && pp.downscale >= 1.0 && pp.downscale <= 16.0, "~downscale must be in [1, 16]", &res);
  require(std::isfinite(pp.pixel_sigma) && pp.pixel_sigma > 0.0, "~pixel_sigma must be > 0 [px]", &res);
  require(std::isfinite(pp.min_depth) && std::isfinite(pp.max_depth) && pp.min_depth > 0.0 && pp.max_depth > pp.min_depth,
          "~min_depth/~max_depth must satisfy 0 < min_depth < max_depth [m]", &res);
  require(std::isfinite(pp.match.max_epipolar_px) && pp.match.max_epipolar_px > 0.0, "~max_epipolar_px must be > 0", &res);
  require(std::isfinite(pp.match.min_disparity) && std::isfinite(pp.match.max_disparity) &&
              pp.match.min_disparity >= 0.0 && pp.match.max_disparity > pp.match.min_disparity,
          "~min_disparity/~max_disparity must satisfy 0 <= min_disparity < max_disparity [px]", &res);
  require(std::isfinite(pp.match.ratio) && pp.match.ratio > 0.0 && pp.match.ratio <= 1.0, "~match_ratio must be in (0, 1]", &res);
  require(pp.match.max_hamming >= 0, "~match_max_hamming must be >= 0 [bits]", &res);
  require(p->queue_size >= 1 && p->queue_size <= 1000, "~queue_size must be in [1, 1000]", &res);
  require(std::isfinite(p->approx_slop) && p->approx_slop > 0.0 && p->approx_slop < 1.0, "~approx_slop must be in (0, 1) [s]", &res);
  require(!p->image_transport.empty(), "~image_transport must name a transport (raw, compressed, ...)", &res);
  require(p->mono16_bits >= 8 && p->mono16_bits <= 16, "~mono16_bits must be in [8, 16]", &res);
  require(std::isfinite(p->max_backwards_jump) && p->max_backwards_jump >= 0.0, "~max_backwards_jump must be >= 0 [s]", &res);
  if (res.ok()) {
    const std::string core = pp.validate();
    if (!core.empty()) res.errors.push_back("pipeline parameters rejected by the core: " + core);
  }

  // Unknown names under ~ are most likely typos of a real parameter.
  std::vector<std::string> all;
  if (ros::param::getParamNames(all)) {
    const std::string prefix = nh.getNamespace() + "/";
    const auto& known = frontendParamNames();
    for (const auto& full : all) {
      if (full.compare(0, prefix.size(), prefix) != 0) continue;
      const std::string rel = full.substr(prefix.size());
      if (rel.find('/') != std::string::npos) continue;  // sub-namespaces: transport plugins etc.
      if (rel == "diagnostic_period") continue;          // diagnostic_updater's own
      if (std::find(known.begin(), known.end(), rel) == known.end())
        res.warnings.push_back("unknown parameter ~" + rel + " ignored (typo?)");
    }
  }
  return res;
}

}  // namespace hapi_frontend
