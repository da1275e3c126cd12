// Band-limited procedural texture for the image-flow tests and benchmark: a
// sum of plane waves, so an image shifted or warped by any sub-pixel amount
// is rendered exactly (no interpolation error in the ground truth).
#pragma once

#include <opencv2/core.hpp>

#include <cmath>
#include <random>
#include <vector>

namespace hapi_frontend_test {

class WaveTexture {
 public:
  // `waves` plane waves with periods 5..40 px, random directions and phases.
  explicit WaveTexture(unsigned seed, int waves = 48) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> angle(0, 2 * M_PI), period(5.0, 40.0);
    for (int i = 0; i < waves; ++i) {
      const double a = angle(rng), k = 2 * M_PI / period(rng);
      waves_.push_back(Wave{k * std::cos(a), k * std::sin(a), angle(rng)});
    }
    amplitude_ = 100.0 / std::sqrt(waves / 2.0);  // about 3 sigma within 0..255
  }

  double at(double x, double y) const {
    double s = 0;
    for (const Wave& w : waves_) s += std::sin(w.kx * x + w.ky * y + w.phase);
    return 128.0 + amplitude_ * s / 3.0;
  }

  // 8-bit image whose pixel (x, y) shows the texture at source(x, y) + noise
  // (Gaussian, noise_sigma grey levels, from `rng`), rounded and saturated.
  template <typename SourceOf>
  cv::Mat render(int width, int height, SourceOf source, double noise_sigma = 0, std::mt19937* rng = nullptr) const {
    cv::Mat img(height, width, CV_8UC1);
    std::normal_distribution<double> noise(0.0, noise_sigma > 0 ? noise_sigma : 1.0);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        double sx = 0, sy = 0;
        source(x, y, &sx, &sy);
        double g = at(sx, sy);
        if (noise_sigma > 0 && rng) g += noise(*rng);
        img.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(std::lround(g));
      }
    return img;
  }

  // The texture moved by the affine flow d(p) = t + G (p - c) (the
  // parameters of hapi_msgs/ImageFlow, G = [a2 a3; a4 a5]): the point at p in
  // the reference image is seen at p + d(p), so pixel q shows the source
  // point p = c + (I + G)^-1 (q - c - t).
  cv::Mat renderAffine(int width, int height, double cu, double cv_, const double a[6], double noise_sigma = 0,
                       std::mt19937* rng = nullptr) const {
    const double m00 = 1 + a[2], m01 = a[3], m10 = a[4], m11 = 1 + a[5];
    const double det = m00 * m11 - m01 * m10;
    return render(
        width, height,
        [&](int x, int y, double* sx, double* sy) {
          const double qx = x - cu - a[0], qy = y - cv_ - a[1];
          *sx = cu + (m11 * qx - m01 * qy) / det;
          *sy = cv_ + (-m10 * qx + m00 * qy) / det;
        },
        noise_sigma, rng);
  }

 private:
  struct Wave {
    double kx, ky, phase;
  };
  std::vector<Wave> waves_;
  double amplitude_ = 0;
};

}  // namespace hapi_frontend_test
