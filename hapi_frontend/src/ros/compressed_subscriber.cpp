#include "compressed_subscriber.hpp"

#include "hapi_frontend/image_header.hpp"

#include <boost/make_shared.hpp>
#include <cv_bridge/cv_bridge.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <pluginlib/class_list_macros.hpp>
#include <ros/console.h>
#include <sensor_msgs/image_encodings.h>

namespace hapi_frontend {

namespace enc = sensor_msgs::image_encodings;

bool decodeCompressed(const sensor_msgs::CompressedImage& in, sensor_msgs::Image* out, std::string* error) {
  *out = sensor_msgs::Image();
  out->header = in.header;
  cv::Mat img;
  // The announced size is checked before OpenCV allocates it.
  *error = in.data.empty() ? std::string() : checkDecodable(in.data.data(), in.data.size(), kMaxDecodedImageBytes);
  try {
    if (!in.data.empty() && error->empty()) {
      const cv::Mat buf(1, static_cast<int>(in.data.size()), CV_8UC1, const_cast<uint8_t*>(in.data.data()));
      img = cv::imdecode(buf, cv::IMREAD_UNCHANGED);
    }
  } catch (const cv::Exception& e) {
    img.release();
    *error = std::string("OpenCV imdecode: ") + e.what();
  }
  // A decoder that read more than the header announced (a header this
  // reader and the codec library understand differently) is refused too.
  if (!img.empty() && img.total() * img.elemSize() > kMaxDecodedImageBytes) {
    *error = "decoded image larger than its header announced";
    img.release();
  }
  if (img.empty()) {
    if (error->empty()) *error = "undecodable data (" + std::to_string(in.data.size()) + " bytes, format '" + in.format + "')";
    out->encoding = enc::MONO8;  // 0x0: counted as malformed by the front end
    return false;
  }
  // The source encoding, as the upstream publisher writes it before ';'.
  std::string named = in.format.substr(0, in.format.find(';'));
  named.erase(0, named.find_first_not_of(' '));
  named.erase(named.find_last_not_of(' ') + 1);
  std::string encoding;
  if (img.channels() == 1) {
    encoding = img.depth() == CV_16U ? enc::MONO16 : enc::MONO8;
  } else if (img.channels() == 3 && img.depth() == CV_8U) {
    encoding = enc::BGR8;  // imdecode's channel order
    if (named == enc::RGB8) {
      cv::cvtColor(img, img, cv::COLOR_BGR2RGB);
      encoding = enc::RGB8;
    }
  } else if (img.channels() == 4 && img.depth() == CV_8U) {
    encoding = enc::BGRA8;
  } else {
    encoding = "unsupported_" + std::to_string(img.channels()) + "ch";
  }
  cv_bridge::CvImage(in.header, encoding, img).toImageMsg(*out);
  return true;
}

void CompressedSubscriber::internalCallback(const sensor_msgs::CompressedImageConstPtr& message,
                                            const Callback& user_cb) {
  auto image = boost::make_shared<sensor_msgs::Image>();
  std::string error;
  if (!decodeCompressed(*message, image.get(), &error)) {
    const ros::WallTime now = ros::WallTime::now();
    if (last_error_log_.isZero() || (now - last_error_log_).toSec() >= 1.0) {
      last_error_log_ = now;
      ROS_ERROR("compressed image on %s: %s", getTopic().c_str(), error.c_str());
    }
  }
  user_cb(image);
}

}  // namespace hapi_frontend

PLUGINLIB_EXPORT_CLASS(hapi_frontend::CompressedSubscriber, image_transport::SubscriberPlugin)
