// The one raw buffer -> 8-bit grey converter (grey_convert.hpp).
#include "hapi_frontend/grey_convert.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace hapi_frontend {
namespace {

InputError fail(const std::string& reason, const std::string& detail) { return InputError{reason, detail}; }

// Bytes per pixel of an accepted encoding, 0 for any other.
int bytesPerPixel(const std::string& e) {
  if (e == "mono8") return 1;
  if (e == "mono16") return 2;
  if (e == "bgr8" || e == "rgb8") return 3;
  if (e == "bgra8" || e == "32FC1") return 4;
  return 0;
}

bool hostIsBigEndian() {
  const std::uint16_t one = 1;
  return *reinterpret_cast<const std::uint8_t*>(&one) == 0;
}

// Percentile p (0..1) of the finite values of a float image, from a regular
// subsample of about 20000 pixels (enough for the 1 % tails, a fraction of a
// millisecond at 640 x 480). false when no value is finite.
bool finitePercentiles(const cv::Mat& f, double p_lo, double p_hi, float* lo, float* hi) {
  const std::size_t total = static_cast<std::size_t>(f.rows) * f.cols;
  const int stride = static_cast<int>(std::max<std::size_t>(1, std::sqrt(total / 20000.0)));
  std::vector<float> v;
  v.reserve(total / (stride * stride) + f.cols);
  for (int y = 0; y < f.rows; y += stride) {
    const float* row = f.ptr<float>(y);
    for (int x = 0; x < f.cols; x += stride)
      if (std::isfinite(row[x])) v.push_back(row[x]);
  }
  if (v.empty()) return false;
  auto at = [&](double p) {
    const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(p * (v.size() - 1) + 0.5));
    std::nth_element(v.begin(), v.begin() + k, v.end());
    return v[k];
  };
  *lo = at(p_lo);
  *hi = at(p_hi);
  return true;
}

// Robust normalisation of a float map to 8 bit (grey_convert.hpp).
void floatToGrey(const cv::Mat& f, cv::Mat* grey) {
  float lo = 0, hi = 0;
  grey->create(f.size(), CV_8UC1);
  if (!finitePercentiles(f, 0.01, 0.99, &lo, &hi)) {
    grey->setTo(0);
    return;
  }
  // A flat map (hi == lo) becomes mid grey: no texture, the tracker finds no
  // features and says so.
  const double scale = hi > lo ? 255.0 / (static_cast<double>(hi) - lo) : 0.0;
  for (int y = 0; y < f.rows; ++y) {
    const float* in = f.ptr<float>(y);
    std::uint8_t* out = grey->ptr<std::uint8_t>(y);
    for (int x = 0; x < f.cols; ++x) {
      if (!std::isfinite(in[x])) {
        out[x] = 0;
        continue;
      }
      const double g = scale > 0 ? (in[x] - lo) * scale : 127.5;
      out[x] = static_cast<std::uint8_t>(std::min(255.0, std::max(0.0, std::round(g))));
    }
  }
}

}  // namespace

const ParamSpec& mono16BitsSpec() {
  // A 16-bit container holds at most 16 significant bits; a camera with 8 or
  // fewer would send mono8.
  static const ParamSpec kSpec =
      ParamSpec::number("mono16_bits", NumberRange::closed(8, 16), "", "significant bits of mono16 images");
  return kSpec;
}

const char* greyEncodingsText() { return "mono8, mono16, bgr8, rgb8, bgra8, 32FC1"; }

InputError convertToGrey(const RawImageView& im, int mono16_bits, cv::Mat* grey) {
  const std::string bad_bits = checkValue(mono16BitsSpec(), mono16_bits);
  if (!bad_bits.empty()) return fail("invalid_setting", bad_bits);
  const int bpp = bytesPerPixel(im.encoding);
  if (bpp == 0)
    return fail("unsupported_encoding",
                "encoding '" + im.encoding + "' (accepted: " + greyEncodingsText() + ")");
  if (im.width == 0 || im.height == 0 || im.data == nullptr) return fail("malformed_image", "image has zero size");
  const std::uint64_t row = static_cast<std::uint64_t>(im.width) * bpp;
  // cv::Mat sizes are int: a side beyond 2^15 is no camera image.
  if (im.width > 1u << 15 || im.height > 1u << 15)
    return fail("malformed_image", "image of " + std::to_string(im.width) + "x" + std::to_string(im.height) +
                                       " px (at most 32768 a side)");
  if (im.step < row || im.size < static_cast<std::uint64_t>(im.step) * im.height) {
    std::ostringstream os;
    os << "buffer does not hold the image: " << im.width << "x" << im.height << " " << im.encoding << ", step "
       << im.step << ", data " << im.size << " bytes";
    return fail("malformed_image", os.str());
  }
  const int type = bpp == 1 ? CV_8UC1 : bpp == 2 ? CV_16UC1 : bpp == 3 ? CV_8UC3 : im.encoding == "bgra8" ? CV_8UC4 : CV_32FC1;
  // cv::Mat only wraps the buffer here; nothing below writes through it.
  const cv::Mat wrapped(static_cast<int>(im.height), static_cast<int>(im.width), type,
                        const_cast<std::uint8_t*>(im.data), im.step);
  try {
    const bool swap = (bpp == 2 || type == CV_32FC1) && im.bigendian != hostIsBigEndian();
    cv::Mat native = wrapped;
    if (swap) {
      native = wrapped.clone();
      for (int y = 0; y < native.rows; ++y) {
        std::uint8_t* p = native.ptr<std::uint8_t>(y);
        for (int x = 0; x < native.cols; ++x) std::reverse(p + x * bpp, p + (x + 1) * bpp);
      }
    }
    if (im.encoding == "mono8") *grey = native;
    else if (im.encoding == "mono16") native.convertTo(*grey, CV_8U, 255.0 / ((1 << mono16_bits) - 1));
    else if (im.encoding == "bgr8") cv::cvtColor(native, *grey, cv::COLOR_BGR2GRAY);
    else if (im.encoding == "rgb8") cv::cvtColor(native, *grey, cv::COLOR_RGB2GRAY);
    else if (im.encoding == "bgra8") cv::cvtColor(native, *grey, cv::COLOR_BGRA2GRAY);
    else floatToGrey(native, grey);
  } catch (const cv::Exception& ex) {
    return fail("conversion_failed", std::string("OpenCV: ") + ex.what());
  }
  return {};
}

}  // namespace hapi_frontend
