// ROS edges of the image-flow tracker (flow_message.hpp).
#include "flow_message.hpp"

#include <algorithm>

namespace hapi_frontend {

void fillFlowMsg(const ImageFlowResult& r, const std_msgs::Header& header, hapi_msgs::ImageFlow* msg) {
  msg->header = header;
  msg->previous_stamp.fromNSec(static_cast<std::uint64_t>(std::max<std::int64_t>(0, r.previous_stamp_ns)));
  msg->u = r.u;
  msg->v = r.v;
  for (int i = 0; i < 6; ++i) {
    msg->affine[i] = r.affine(i);
    for (int j = 0; j < 6; ++j) msg->affine_covariance[6 * i + j] = r.covariance(i, j);
  }
  msg->inliers = r.inliers;
  msg->tracked = r.tracked;
  msg->status = static_cast<std::uint8_t>(r.status);
  static_assert(static_cast<int>(FlowStatus::kOk) == hapi_msgs::ImageFlow::STATUS_OK &&
                    static_cast<int>(FlowStatus::kTooFewFeatures) == hapi_msgs::ImageFlow::STATUS_TOO_FEW_FEATURES &&
                    static_cast<int>(FlowStatus::kFirstFrame) == hapi_msgs::ImageFlow::STATUS_FIRST_FRAME,
                "FlowStatus follows hapi_msgs/ImageFlow");
}

}  // namespace hapi_frontend
