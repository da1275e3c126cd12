// DenseDepthProcessor (dense_depth_nodelet_processor.hpp).
#include "dense_depth_nodelet_processor.hpp"

#include "image_input.hpp"

#include "hapi_surface/depth_image_contract.hpp"

#include <boost/make_shared.hpp>
#include <hapi_dataset/ros/bag_messages.hpp>

#include <algorithm>
#include <cmath>

namespace hapi_surface {
namespace {

sensor_msgs::ImagePtr imageMsg(const cv::Mat& m, const std_msgs::Header& header) {
  return boost::make_shared<sensor_msgs::Image>(hapi_dataset::toImageMsg(m, header));
}

// The depth image's camera: the rectified, scaled left projection.
sensor_msgs::CameraInfoPtr depthInfo(const RectifiedGeometry& g, const std_msgs::Header& header) {
  CameraInfoData c;
  c.width = g.width;
  c.height = g.height;
  c.D.assign(5, 0.0);
  c.K = {g.fx, 0, g.cx, 0, g.fy, g.cy, 0, 0, 1};
  c.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  c.P = {g.fx, 0, g.cx, 0, 0, g.fy, g.cy, 0, 0, 0, 1, 0};
  return boost::make_shared<sensor_msgs::CameraInfo>(hapi_dataset::toCameraInfoMsg(c, header));
}

}  // namespace

CameraInfoData toCameraInfoData(const sensor_msgs::CameraInfo& msg) {
  CameraInfoData c;
  c.width = static_cast<int>(std::min<uint32_t>(msg.width, 1u << 20));
  c.height = static_cast<int>(std::min<uint32_t>(msg.height, 1u << 20));
  c.distortion_model = msg.distortion_model;
  c.D = msg.D;
  std::copy(msg.K.begin(), msg.K.end(), c.K.begin());
  std::copy(msg.R.begin(), msg.R.end(), c.R.begin());
  std::copy(msg.P.begin(), msg.P.end(), c.P.begin());
  return c;
}

DenseDepthProcessor::DenseDepthProcessor(const DenseDepthNodeletParams& params)
    : params_(params), matcher_(params.depth) {}

InputError DenseDepthProcessor::updateRectifier(const sensor_msgs::CameraInfo& left,
                                                const sensor_msgs::CameraInfo& right) {
  const CameraInfoData l = toCameraInfoData(left), r = toCameraInfoData(right);
  if (rectifier_ && rectifier_->builtFrom(l, r, params_.depth.image_scale)) return {};
  rectifier_.reset();
  const std::string why = StereoRectifier::check(l, r);
  if (!why.empty()) return {"invalid_calibration", why};
  rectifier_ = std::make_unique<StereoRectifier>(l, r, params_.depth.image_scale);
  return {};
}

InputError DenseDepthProcessor::process(const sensor_msgs::ImageConstPtr& left,
                                        const sensor_msgs::CameraInfoConstPtr& left_info,
                                        const sensor_msgs::ImageConstPtr& right,
                                        const sensor_msgs::CameraInfoConstPtr& right_info, DepthMessages* out) {
  hapi_frontend::GreyImage l, r;
  if (InputError e = hapi_frontend::toGrey(left, params_.mono16_bits, &l)) return {e.reason, "left: " + e.detail};
  if (InputError e = hapi_frontend::toGrey(right, params_.mono16_bits, &r)) return {e.reason, "right: " + e.detail};
  if (InputError e = hapi_frontend::checkPairSizes(l, r, *left_info, *right_info)) return e;
  std_msgs::Header header = left->header;
  if (header.frame_id.empty()) header.frame_id = left_info->header.frame_id;
  if (header.frame_id.empty()) return {"missing_frame_id", "left image and camera_info have no frame_id"};
  if (InputError e = updateRectifier(*left_info, *right_info)) return e;
  cv::Mat lr, rr;
  rectifier_->rectify(l.gray, r.gray, &lr, &rr);
  DepthImage depth;
  const std::string why = matcher_.compute(lr, rr, rectifier_->geometry(), &depth);
  if (!why.empty()) return {"core_rejected", why};
  cv::Mat confidence8;
  depth.confidence.convertTo(confidence8, CV_8U, kConfidenceMono8One);
  out->depth = imageMsg(depth.depth, header);            // 32FC1
  out->confidence = imageMsg(confidence8, header);       // mono8
  out->camera_info = depthInfo(rectifier_->geometry(), header);
  out->valid_fraction = static_cast<double>(cv::countNonZero(depth.confidence > 0)) / depth.confidence.total();
  return {};
}

}  // namespace hapi_surface
