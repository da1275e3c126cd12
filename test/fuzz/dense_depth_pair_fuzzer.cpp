// libFuzzer target: sensor_msgs/Image + CameraInfo pairs through
// DenseDepthNodelet's input path as its worker runs it
// (DenseDepthProcessor::process): roscpp deserialisation, the front end's
// toGrey and pair size checks, CameraInfo -> StereoRectifier (hostile K, D,
// R, P: NaN, zero, huge, wrong counts), rectification, SGBM with the
// left-right check, and the output messages. The processor persists across
// the pairs of one input (its rectifier is kept until the CameraInfo pair
// changes), as in the nodelet. Input: the image_pair target's format, up to
// 3 groups of 4 records (left image, right image, left info, right info;
// bounded_message.hpp).
#include "stereo_pair_records.hpp"

#include "dense_depth_nodelet_processor.hpp"

#include <ros/time.h>

#include <opencv2/core/utility.hpp>

#include <cmath>
#include <cstdlib>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ros::Time::init();
  cv::setNumThreads(0);  // one thread: reproducible, and no leak reports from a worker pool at exit
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hapi_surface;
  DenseDepthProcessor processor{DenseDepthNodeletParams()};
  hapi_fuzz::Records records(data, size);
  for (int pair = 0; pair < 3; ++pair) {
    hapi_fuzz::StereoPairMsgs m;
    const hapi_fuzz::PairRead read = hapi_fuzz::nextPair(&records, &m);
    if (read == hapi_fuzz::PairRead::kEnd) break;
    if (read == hapi_fuzz::PairRead::kRejected) continue;
    DepthMessages out;
    try {
      if (processor.process(m.left, m.left_info, m.right, m.right_info, &out)) continue;
    } catch (const std::exception&) {
      continue;  // the nodelet's worker catches these too (internal_error); a crash is what this looks for
    }
    // What leaves: sizes that match the camera_info, depth in range or NaN.
    if (out.depth->width != out.camera_info->width || out.confidence->height != out.camera_info->height) std::abort();
    const float* z = reinterpret_cast<const float*>(out.depth->data.data());
    for (std::size_t i = 0; i < out.depth->data.size() / 4; ++i)
      if (!std::isnan(z[i]) && !(z[i] > 0)) std::abort();
  }
  return 0;
}
