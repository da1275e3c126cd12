// The stereo targets' input (image_pair, dense_depth_pair): groups of 4
// records, left image, right image, left CameraInfo, right CameraInfo
// (bounded_message.hpp), read one group at a time.
#pragma once

#include "bounded_message.hpp"

#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <boost/make_shared.hpp>

namespace hapi_fuzz {

struct StereoPairMsgs {
  sensor_msgs::ImagePtr left, right;
  sensor_msgs::CameraInfoPtr left_info, right_info;
};

enum class PairRead { kEnd, kRejected, kOk };

// kEnd: fewer than 4 records left; kRejected: roscpp refused one of the 4.
inline PairRead nextPair(Records* records, StereoPairMsgs* out) {
  const std::uint8_t* rec[4];
  std::size_t len[4];
  for (int i = 0; i < 4; ++i)
    if (!records->next(&rec[i], &len[i])) return PairRead::kEnd;
  out->left = boost::make_shared<sensor_msgs::Image>();
  out->right = boost::make_shared<sensor_msgs::Image>();
  out->left_info = boost::make_shared<sensor_msgs::CameraInfo>();
  out->right_info = boost::make_shared<sensor_msgs::CameraInfo>();
  const bool ok = deserialise<sensor_msgs::Image_>(rec[0], len[0], out->left.get()) &&
                  deserialise<sensor_msgs::Image_>(rec[1], len[1], out->right.get()) &&
                  deserialise<sensor_msgs::CameraInfo_>(rec[2], len[2], out->left_info.get()) &&
                  deserialise<sensor_msgs::CameraInfo_>(rec[3], len[3], out->right_info.get());
  return ok ? PairRead::kOk : PairRead::kRejected;
}

}  // namespace hapi_fuzz
