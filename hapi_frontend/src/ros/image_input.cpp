#include "image_input.hpp"

#include <cv_bridge/cv_bridge.h>
#include <opencv2/imgproc.hpp>
#include <sensor_msgs/image_encodings.h>

#include <cmath>
#include <sstream>

namespace hapi_frontend {
namespace enc = sensor_msgs::image_encodings;

namespace {
InputError err(const std::string& reason, const std::string& detail) { return InputError{reason, detail}; }
std::string sizeText(const cv::Mat& m) { return std::to_string(m.cols) + "x" + std::to_string(m.rows); }
}  // namespace

InputError toGrey(const sensor_msgs::ImageConstPtr& msg, int mono16_bits, GreyImage* out) {
  if (!msg) return err("malformed_image", "null image message");
  const std::string& e = msg->encoding;
  int bytes_per_px = 0;
  if (e == enc::MONO8) bytes_per_px = 1;
  else if (e == enc::BGR8 || e == enc::RGB8) bytes_per_px = 3;
  else if (e == enc::MONO16) bytes_per_px = 2;
  else return err("unsupported_encoding", "encoding '" + e + "' (accepted: mono8, bgr8, rgb8, mono16)");

  // cv_bridge wraps the buffer without checking its length: a truncated
  // message would be read out of bounds, so check before converting.
  if (msg->width == 0 || msg->height == 0) return err("malformed_image", "image has zero size");
  const uint64_t row = static_cast<uint64_t>(msg->width) * bytes_per_px;
  if (msg->step < row || msg->data.size() < static_cast<uint64_t>(msg->step) * msg->height) {
    std::ostringstream os;
    os << "buffer too short: " << msg->width << "x" << msg->height << " " << e << ", step " << msg->step
       << ", data " << msg->data.size() << " bytes";
    return err("malformed_image", os.str());
  }

  try {
    out->keep_alive = msg;
    out->colour.release();
    if (e == enc::MONO8) {
      out->gray = cv_bridge::toCvShare(msg, enc::MONO8)->image;
    } else if (e == enc::BGR8) {
      out->colour = cv_bridge::toCvShare(msg, enc::BGR8)->image;
      cv::cvtColor(out->colour, out->gray, cv::COLOR_BGR2GRAY);
    } else if (e == enc::RGB8) {
      const cv::Mat rgb = cv_bridge::toCvShare(msg, enc::RGB8)->image;
      cv::cvtColor(rgb, out->colour, cv::COLOR_RGB2BGR);
      cv::cvtColor(rgb, out->gray, cv::COLOR_RGB2GRAY);
    } else {  // mono16
      // A fixed scale (not per-frame min/max) keeps FAST thresholds meaning
      // the same intensity step in every frame.
      const cv::Mat m16 = cv_bridge::toCvShare(msg, enc::MONO16)->image;
      m16.convertTo(out->gray, CV_8U, 255.0 / ((1 << mono16_bits) - 1));
    }
  } catch (const cv_bridge::Exception& ex) {
    return err("conversion_failed", std::string("cv_bridge: ") + ex.what());
  } catch (const cv::Exception& ex) {
    return err("conversion_failed", std::string("OpenCV: ") + ex.what());
  }
  return {};
}

InputError toCalib(const sensor_msgs::CameraInfo& info, CameraCalib* c) {
  *c = copyCameraInfo(info);

  for (double v : c->K) if (!std::isfinite(v)) return err("invalid_calibration", "K contains NaN/Inf");
  for (double v : c->P) if (!std::isfinite(v)) return err("invalid_calibration", "P contains NaN/Inf");
  for (double v : c->D) if (!std::isfinite(v)) return err("invalid_calibration", "D contains NaN/Inf");
  // A driver that publishes R = 0 (never calibrated) would make the rig singular.
  bool r_zero = true;
  for (double v : c->R) r_zero = r_zero && v == 0.0;
  if (r_zero) return err("invalid_calibration", "R is all zeros (uncalibrated camera?)");
  if (!c->D.empty()) {
    if (c->distortion_model == "plumb_bob" && c->D.size() != 5)
      return err("invalid_calibration", "plumb_bob needs 5 coefficients, got " + std::to_string(c->D.size()));
    if (c->distortion_model == "rational_polynomial" && c->D.size() != 8)
      return err("invalid_calibration", "rational_polynomial needs 8 coefficients, got " + std::to_string(c->D.size()));
  }
  if (info.binning_x > 1 || info.binning_y > 1)
    return err("invalid_calibration", "binning is not supported (publish full-resolution CameraInfo)");
  const auto& roi = info.roi;
  const bool full_roi = (roi.width == 0 && roi.height == 0) ||
                        (roi.x_offset == 0 && roi.y_offset == 0 && roi.width == info.width && roi.height == info.height);
  if (!full_roi) return err("invalid_calibration", "a sub-window ROI is not supported");
  const std::string why = c->validate();
  if (!why.empty()) return err("invalid_calibration", why);
  return {};
}

InputError checkPairSizes(const GreyImage& left, const GreyImage& right, const sensor_msgs::CameraInfo& left_info,
                          const sensor_msgs::CameraInfo& right_info) {
  if (left.gray.size() != right.gray.size())
    return err("size_mismatch", "left " + sizeText(left.gray) + " vs right " + sizeText(right.gray));
  if (static_cast<int>(left_info.width) != left.gray.cols || static_cast<int>(left_info.height) != left.gray.rows ||
      static_cast<int>(right_info.width) != right.gray.cols || static_cast<int>(right_info.height) != right.gray.rows) {
    std::ostringstream os;
    os << "images " << sizeText(left.gray) << " but camera_info " << left_info.width << "x" << left_info.height
       << " / " << right_info.width << "x" << right_info.height;
    return err("calibration_size_mismatch", os.str());
  }
  return {};
}

}  // namespace hapi_frontend
