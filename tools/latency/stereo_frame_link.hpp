// The link between the two nodelets without ROS: the StereoFrame the back
// end receives for one front-end result. Through ROS the result travels as
// hapi_msgs/StereoLandmarks (the front end's fillLandmarksMsg, the back end's
// toStereoFrame); this is the same mapping field for field: the measurement
// id is the landmark's index in the result, position and covariance in the
// left optical frame, detector response, colour and the left-image
// descriptors. test/latency_link_test.cpp holds it equal to the message path.
#pragma once

#include <hapi_eskf/types.hpp>
#include <hapi_frontend/stereo_pipeline.hpp>

#include <cstring>
#include <string>

namespace hapi_latency {

// False with *error when the front end would not publish the result
// (hapi_frontend::publishProblem).
inline bool toStereoFrame(const hapi_frontend::StereoFrameResult& r, double stamp, hapi_eskf::StereoFrame* out,
                          std::string* error) {
  *error = hapi_frontend::publishProblem(r);
  if (!error->empty()) return false;
  const std::size_t n = r.landmarks.size();
  const cv::Mat& d = r.descriptors;
  out->stamp = stamp;
  out->descriptor_length =
      n > 0 ? d.cols : (r.descriptor_type == hapi_frontend::DescriptorType::AKAZE ? 61 : 32);
  out->descriptors.resize(n * out->descriptor_length);
  out->measurements.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const hapi_frontend::StereoLandmarkOut& in = r.landmarks[i];
    std::memcpy(&out->descriptors[i * out->descriptor_length], d.ptr<uint8_t>(static_cast<int>(i)),
                out->descriptor_length);
    hapi_eskf::StereoMeasurement& m = out->measurements[i];
    m.z = in.position;
    m.Cz = in.covariance;
    m.frontend_id = static_cast<uint32_t>(i);
    m.response = in.response;
    m.rgb = in.rgb;
  }
  return true;
}

}  // namespace hapi_latency
