// libFuzzer target: sensor_msgs/Image + CameraInfo pairs through the front
// end's input path as StereoFrontendNodelet::processFrame runs it: roscpp
// deserialisation, toGrey (encodings, truncated buffers), the pair's size
// checks, toCalib and the pipeline's calibration, then StereoPipeline::process
// (CPU: ORB, stereo matching, refinement, MMSE triangulation) and the
// landmarks message. The pipeline persists across the pairs of one input (a
// calibration is kept until a different one arrives), as in the nodelet.
// Input: up to 3 groups of 4 records (left image, right image, left info,
// right info; bounded_message.hpp).
#include "stereo_pair_records.hpp"

#include "image_input.hpp"
#include "landmarks_message.hpp"

#include "hapi_frontend/stereo_pipeline.hpp"

#include <hapi_msgs/StereoLandmarks.h>
#include <ros/console.h>
#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <boost/make_shared.hpp>
#include <opencv2/core/utility.hpp>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ros::Time::init();
  cv::setNumThreads(0);  // one thread: reproducible, and no leak reports from a worker pool at exit
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hapi_frontend;
  PipelineParams params;
  params.detector_features = 200;
  StereoPipeline pipeline(params);
  hapi_fuzz::Records records(data, size);
  for (int pair = 0; pair < 3; ++pair) {
    hapi_fuzz::StereoPairMsgs m;
    const hapi_fuzz::PairRead read = hapi_fuzz::nextPair(&records, &m);
    if (read == hapi_fuzz::PairRead::kEnd) break;
    if (read == hapi_fuzz::PairRead::kRejected) continue;
    const sensor_msgs::ImagePtr& left = m.left;
    const sensor_msgs::ImagePtr& right = m.right;
    const sensor_msgs::CameraInfo& left_info = *m.left_info;
    const sensor_msgs::CameraInfo& right_info = *m.right_info;
    GreyImage l, r;
    if (toGrey(left, 16, &l) || toGrey(right, 16, &r)) continue;
    if (checkPairSizes(l, r, left_info, right_info)) continue;
    CameraCalib cl, cr;
    if (toCalib(left_info, &cl) || toCalib(right_info, &cr)) continue;
    if (!pipeline.setCalibration(cl, cr).empty()) continue;
    StereoFrameResult result;
    if (!pipeline.process(l.gray, r.gray, l.colour, &result).empty()) continue;
    hapi_msgs::StereoLandmarks msg;
    fillLandmarksMsg(result, left->header, &msg);
  }
  return 0;
}
