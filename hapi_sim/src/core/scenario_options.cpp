// The scenario's command-line options (scenario_options.hpp).
#include "hapi_sim/scenario_options.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>

#include <Eigen/Core>

#include "hapi_dataset/command_line.hpp"

namespace hapi_sim {
namespace {

// "U,V": two numbers >= 0 (pixels).
Eigen::Vector2d parsePixelArg(const std::string& k, const std::string& v) {
  const size_t comma = v.find(',');
  if (comma == std::string::npos) throw std::invalid_argument(k + " must be U,V (pixels), got '" + v + "'");
  const Eigen::Vector2d px(hapi_dataset::parseNumberArg(k, v.substr(0, comma)),
                           hapi_dataset::parseNumberArg(k, v.substr(comma + 1)));
  if (!(px.x() >= 0 && px.y() >= 0)) throw std::invalid_argument(k + " must be U,V with U, V >= 0, got '" + v + "'");
  return px;
}

// "X,Y,Z,YAW_DEG": the scene's placement (ScenarioConfig::scene_shift, scene_yaw).
void parseSceneOffset(const std::string& k, const std::string& v, ScenarioConfig* cfg) {
  double x[4];
  size_t start = 0;
  for (int i = 0; i < 4; ++i) {
    const size_t comma = i < 3 ? v.find(',', start) : v.size();
    if (comma == std::string::npos) throw std::invalid_argument(k + " must be X,Y,Z,YAW_DEG, got '" + v + "'");
    x[i] = hapi_dataset::parseNumberArg(k, v.substr(start, comma - start));
    start = comma + 1;
  }
  if (start <= v.size()) throw std::invalid_argument(k + " must be X,Y,Z,YAW_DEG, got '" + v + "'");
  cfg->scene_shift = Eigen::Vector3d(x[0], x[1], x[2]);
  cfg->scene_yaw = x[3] * M_PI / 180.0;
}

}  // namespace

const char* const kScenarioOptionsUsage =
    "--scene globe|skin|patch|chessboard\n"
    "  --trajectory smooth|handheld|fast|loop|subject|rest|orbit|measurement|measurement_subject|stage|tremor|calibration\n"
    "  [--seed N] [--duration S] [--rate HZ] [--imu-rate HZ] [--exposure-ms MS] [--blur-samples N]\n"
    "  [--photometric 0|1] [--image-noise 0|1] [--imu-noise 0|1] [--image-scale S] [--texture PATH]\n"
    "  [--realism ideal|real] [--imaging-rate HZ (0: none)] [--imaging-pixel U,V (default: the centre)]\n"
    "  [--imaging-content texture|perfusion (default texture)]\n"
    "  [--stage-speed MM_S (stage; default 5)]\n"
    "  [--right-shift-px PX (right image shifted down: bad rectification)]\n"
    "  [--camera-clock-offset S (added to camera stamps: clocks that disagree)]\n"
    "  [--scene-offset X,Y,Z,YAW_DEG (the scene placed elsewhere: moved X,Y,Z m, turned about the vertical)]\n"
    "  [--lighting-gain G (every image's gain times G: another lighting; default 1)]\n"
    "  [--skin-texture-seed N (skin: another skin's texture; default 0, the reference skin)]";

bool setScenarioOption(const std::string& k, const std::string& v, ScenarioConfig* cfg) {
  using hapi_dataset::parseFlagArg;
  using hapi_dataset::parseIntegerArg;
  using hapi_dataset::parseNumberArg;
  if (k == "--scene") {
    if (!parseSceneKind(v, &cfg->scene)) throw std::invalid_argument("--scene must be globe, skin, patch or chessboard");
  } else if (k == "--trajectory") {
    if (!parseTrajectoryKind(v, &cfg->trajectory)) throw std::invalid_argument("unknown --trajectory " + v);
  } else if (k == "--seed") {
    cfg->seed = static_cast<uint32_t>(parseIntegerArg(k, v, 0, 4294967295LL));
  } else if (k == "--duration") {
    cfg->duration = parseNumberArg(k, v);
  } else if (k == "--rate") {
    cfg->rate = parseNumberArg(k, v);
  } else if (k == "--imu-rate") {
    cfg->imu_rate = parseNumberArg(k, v);
  } else if (k == "--exposure-ms") {
    cfg->exposure = 1e-3 * parseNumberArg(k, v);
  } else if (k == "--blur-samples") {
    cfg->blur_samples = static_cast<int>(parseIntegerArg(k, v, -1, 1000));
  } else if (k == "--photometric") {
    cfg->photometric = parseFlagArg(k, v);
  } else if (k == "--image-noise") {
    cfg->image_noise = parseFlagArg(k, v);
  } else if (k == "--imu-noise") {
    cfg->imu_noise = parseFlagArg(k, v);
  } else if (k == "--image-scale") {
    cfg->image_scale = parseNumberArg(k, v);
  } else if (k == "--realism") {
    if (!parseRealism(v, &cfg->realism)) throw std::invalid_argument("--realism must be ideal or real");
  } else if (k == "--imaging-rate") {
    cfg->imaging_rate = parseNumberArg(k, v);
  } else if (k == "--imaging-content") {
    if (!parseImagingContent(v, &cfg->imaging_content))
      throw std::invalid_argument("--imaging-content must be texture or perfusion");
  } else if (k == "--imaging-pixel") {
    cfg->imaging_pixel = parsePixelArg(k, v);
  } else if (k == "--stage-speed") {
    cfg->stage_speed = 1e-3 * parseNumberArg(k, v);
  } else if (k == "--right-shift-px") {
    cfg->right_shift_px = parseNumberArg(k, v);
  } else if (k == "--camera-clock-offset") {
    cfg->camera_clock_offset = parseNumberArg(k, v);
  } else if (k == "--scene-offset") {
    parseSceneOffset(k, v, cfg);
  } else if (k == "--skin-texture-seed") {
    cfg->skin_texture_seed = static_cast<uint32_t>(parseIntegerArg(k, v, 0, 1000000));
  } else if (k == "--lighting-gain") {
    cfg->lighting_gain = parseNumberArg(k, v);
  } else if (k == "--texture") {
    cfg->globe_texture = v;
  } else {
    return false;
  }
  return true;
}

}  // namespace hapi_sim
