// frontend_replay: the stereo front end run offline on every stereo pair of a
// bag. Writes OUT.bag with the landmarks (hapi_msgs/StereoLandmarks, the
// nodelet's message, built by the same conversion) and every message of
// IN.bag that is not an image or camera info (IMU, TF, ground truth, scene
// descriptions), in bag-time order with their connection headers (latched
// topics stay latched). Every pair is processed, none dropped, so the back
// end's offline replay (hapi_eskf eskf_replay, after dump_frames.py) sees the
// stream the live system produces on an unloaded machine, deterministically.
//
//   frontend_replay IN.bag OUT.bag [--left T] [--right T] [--left-info T] [--right-info T] [--landmarks T]
//                   [name=value ...]
//
// Defaults: /stereo/{left,right}/image_raw, /stereo/{left,right}/camera_info,
// /stereo_frontend/landmarks (the topics of launch/all_in_one.launch). The
// pipeline runs with the defaults of config/frontend.yaml (PipelineParams);
// name=value sets a pipeline parameter by its ROS name (fast_threshold=8),
// checked against its declared range.
// Pairs are matched by exact stamp (a hardware-triggered rig, the
// front end's default approximate_sync: false).
#include "image_input.hpp"
#include "landmarks_message.hpp"

#include <hapi_frontend/stereo_pipeline.hpp>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <cstdio>
#include <iostream>
#include <map>
#include <string>

namespace {

struct Topics {
  std::string left = "/stereo/left/image_raw", right = "/stereo/right/image_raw";
  std::string left_info = "/stereo/left/camera_info", right_info = "/stereo/right/camera_info";
  std::string landmarks = "/stereo_frontend/landmarks";
};

int usage(const char* why) {
  std::cerr << "frontend_replay: " << why << "\n"
            << "usage: frontend_replay IN.bag OUT.bag [--left T] [--right T] [--left-info T] [--right-info T] "
               "[--landmarks T] [name=value ...]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage("need IN.bag and OUT.bag");
  Topics t;
  hapi_frontend::PipelineParams params;
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    const auto eq = a.find('=');
    if (eq != std::string::npos) {
      const std::string error = hapi_frontend::setFromText(&params, a.substr(0, eq), a.substr(eq + 1));
      if (!error.empty()) return usage(error.c_str());
      continue;
    }
    if (i + 1 >= argc) return usage(("missing value after " + a).c_str());
    const std::string v = argv[++i];
    if (a == "--left") t.left = v;
    else if (a == "--right") t.right = v;
    else if (a == "--left-info") t.left_info = v;
    else if (a == "--right-info") t.right_info = v;
    else if (a == "--landmarks") t.landmarks = v;
    else return usage(("unknown option " + a).c_str());
  }
  try {
    rosbag::Bag in(argv[1], rosbag::bagmode::Read);
    rosbag::Bag out(argv[2], rosbag::bagmode::Write);
    const std::string invalid = params.validate();
    if (!invalid.empty()) return usage(invalid.c_str());
    hapi_frontend::StereoPipeline pipeline(params);
    sensor_msgs::CameraInfo left_info, right_info;
    bool have_left_info = false, have_right_info = false, calibrated = false;
    std::map<ros::Time, sensor_msgs::ImageConstPtr> lefts, rights;  // waiting for their partner
    int pairs = 0, published = 0, rejected = 0;

    auto processPair = [&](const sensor_msgs::ImageConstPtr& l, const sensor_msgs::ImageConstPtr& r,
                           const ros::Time& when) {
      ++pairs;
      if (!calibrated) {
        if (!have_left_info || !have_right_info) {
          ++rejected;
          return;
        }
        hapi_frontend::CameraCalib cl, cr;
        if (hapi_frontend::toCalib(left_info, &cl) || hapi_frontend::toCalib(right_info, &cr))
          throw std::runtime_error("unusable camera_info");
        const std::string why = pipeline.setCalibration(cl, cr);
        if (!why.empty()) throw std::runtime_error("calibration: " + why);
        calibrated = true;
      }
      hapi_frontend::GreyImage gl, gr;
      // mono16 input: all 16 bits significant (the nodelet's ~mono16_bits default).
      if (hapi_frontend::toGrey(l, 16, &gl) || hapi_frontend::toGrey(r, 16, &gr)) {
        ++rejected;
        return;
      }
      hapi_frontend::StereoFrameResult res;
      if (!pipeline.process(gl.gray, gr.gray, gl.colour, &res).empty()) {
        ++rejected;
        return;
      }
      hapi_msgs::StereoLandmarks msg;
      if (!hapi_frontend::fillLandmarksMsg(res, l->header, &msg).empty()) {
        ++rejected;
        return;
      }
      out.write(t.landmarks, when, msg);
      ++published;
    };

    rosbag::View view(in);
    for (const rosbag::MessageInstance& m : view) {
      const std::string& topic = m.getTopic();
      if (topic == t.left_info || topic == t.right_info) {
        const auto info = m.instantiate<sensor_msgs::CameraInfo>();
        if (!info) continue;
        if (topic == t.left_info && !have_left_info) left_info = *info, have_left_info = true;
        if (topic == t.right_info && !have_right_info) right_info = *info, have_right_info = true;
        continue;
      }
      if (topic == t.left || topic == t.right) {
        const auto img = m.instantiate<sensor_msgs::Image>();
        if (!img) continue;
        auto& mine = topic == t.left ? lefts : rights;
        auto& other = topic == t.left ? rights : lefts;
        const auto it = other.find(img->header.stamp);
        if (it == other.end()) {
          mine[img->header.stamp] = img;
          continue;
        }
        const sensor_msgs::ImageConstPtr partner = it->second;
        other.erase(other.begin(), std::next(it));  // older unpaired images never find a partner
        processPair(topic == t.left ? img : partner, topic == t.left ? partner : img, m.getTime());
        continue;
      }
      out.write(topic, m.getTime(), m, m.getConnectionHeader());
    }
    out.close();
    std::printf("frontend_replay: %d stereo pairs, %d landmark messages written to %s, %d not usable\n", pairs,
                published, argv[2], rejected);
    return published > 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "frontend_replay: " << e.what() << "\n";
    return 1;
  }
}
