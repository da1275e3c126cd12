// Test images of the dense depth gtests: a smooth random speckle, the
// texture a stereo matcher can lock on to, deterministic per seed.
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace hapi_surface {
namespace test_images {

inline cv::Mat speckle(cv::Size size, int seed) {
  cv::RNG rng(seed);
  cv::Mat noise(size, CV_32F);
  rng.fill(noise, cv::RNG::NORMAL, 0, 60);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 1.2);
  cv::Mat out;
  noise.convertTo(out, CV_8U, 1.0, 128);
  return out;
}

}  // namespace test_images
}  // namespace hapi_surface
