#include "frames.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace hapi_frontend {
namespace gpu_test {

namespace {

// Small deterministic generator (same numbers on every platform, unlike
// std::uniform_*_distribution).
struct Lcg {
  uint64_t s;
  explicit Lcg(uint64_t seed) : s(seed * 6364136223846793005ULL + 1442695040888963407ULL) {}
  uint32_t next() {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<uint32_t>(s >> 33);
  }
  int uniform(int lo, int hi) { return lo + static_cast<int>(next() % static_cast<uint32_t>(hi - lo + 1)); }
};

struct Shape {
  bool disc;
  int cx, cy, rx, ry, disparity;
  int base, amp, period, phase;  // striped texture inside the shape
};

void blur121(std::vector<int>& img, int w, int h) {
  std::vector<int> t(img.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int* r = &img[static_cast<size_t>(y) * w];
      t[static_cast<size_t>(y) * w + x] = r[std::max(x - 1, 0)] + 2 * r[x] + r[std::min(x + 1, w - 1)];
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int a = t[static_cast<size_t>(std::max(y - 1, 0)) * w + x], b = t[static_cast<size_t>(y) * w + x],
                c = t[static_cast<size_t>(std::min(y + 1, h - 1)) * w + x];
      img[static_cast<size_t>(y) * w + x] = (a + 2 * b + c + 8) / 16;
    }
}

void render(int w, int h, const std::vector<Shape>& shapes, bool right, uint32_t noise_seed, int noise, Frame& f) {
  std::vector<int> img(static_cast<size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img[static_cast<size_t>(y) * w + x] = 60 + (x * 60) / std::max(w, 1) + (y * 40) / std::max(h, 1);
  for (const Shape& s : shapes) {  // painter's order: later shapes occlude earlier ones
    const int cx = s.cx - (right ? s.disparity : 0);
    for (int y = std::max(0, s.cy - s.ry); y <= std::min(h - 1, s.cy + s.ry); ++y)
      for (int x = std::max(0, cx - s.rx); x <= std::min(w - 1, cx + s.rx); ++x) {
        const int dx = x - cx, dy = y - s.cy;
        if (s.disc && static_cast<long long>(dx) * dx * s.ry * s.ry + static_cast<long long>(dy) * dy * s.rx * s.rx >
                          static_cast<long long>(s.rx) * s.rx * s.ry * s.ry)
          continue;
        // Random-block texture in shape coordinates (moves with the shape):
        // unique corners, unlike periodic stripes which defeat the ratio test.
        const int cu = (dx + 4096) / s.period, cv = (dy + 4096) / s.period;
        uint32_t hsh = static_cast<uint32_t>(cu) * 73856093u ^ static_cast<uint32_t>(cv) * 19349663u ^
                       static_cast<uint32_t>(s.phase) * 83492791u;
        hsh ^= hsh >> 13;
        hsh *= 0x5bd1e995u;
        hsh ^= hsh >> 15;
        img[static_cast<size_t>(y) * w + x] = s.base + static_cast<int>(hsh % static_cast<uint32_t>(2 * s.amp + 1)) - s.amp;
      }
  }
  blur121(img, w, h);
  blur121(img, w, h);
  Lcg n(noise_seed);
  f.width = w;
  f.height = h;
  f.pixels.resize(img.size());
  for (size_t k = 0; k < img.size(); ++k) {
    const int v = img[k] + (noise > 0 ? n.uniform(-noise, noise) : 0);
    f.pixels[k] = static_cast<uint8_t>(std::max(0, std::min(255, v)));
  }
}

}  // namespace

void renderStereoPair(int width, int height, uint32_t seed, int max_disparity, int noise, Frame& left, Frame& right) {
  Lcg r(seed);
  std::vector<Shape> shapes;
  const int n = 40 + (width * height) / 4000;
  for (int k = 0; k < n; ++k) {
    Shape s;
    s.disc = r.next() & 1;
    s.cx = r.uniform(0, width + max_disparity);
    s.cy = r.uniform(0, height - 1);
    s.rx = r.uniform(6, std::max(8, width / 8));
    s.ry = r.uniform(6, std::max(8, height / 8));
    s.disparity = r.uniform(1, std::max(1, max_disparity));
    s.base = r.uniform(40, 215);
    s.amp = r.uniform(10, 40);
    s.period = r.uniform(4, 14);
    s.phase = r.uniform(0, 100000);
    shapes.push_back(s);
  }
  // Nearer shapes (larger disparity) are painted last.
  std::stable_sort(shapes.begin(), shapes.end(), [](const Shape& a, const Shape& b) { return a.disparity < b.disparity; });
  render(width, height, shapes, false, seed * 2 + 1, noise, left);
  render(width, height, shapes, true, seed * 2 + 2, noise, right);
  left.name = "procedural_L_" + std::to_string(seed);
  right.name = "procedural_R_" + std::to_string(seed);
}

bool loadPgm(const std::string& path, Frame& f, std::string* err) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (err) *err = "cannot open " + path;
    return false;
  }
  std::string magic;
  in >> magic;
  auto token = [&](int& v) {
    in >> std::ws;
    while (in.peek() == '#') {  // comment lines
      std::string line;
      std::getline(in, line);
      in >> std::ws;
    }
    return static_cast<bool>(in >> v);
  };
  int w = 0, h = 0, maxval = 0;
  if (magic != "P5" || !token(w) || !token(h) || !token(maxval) || w <= 0 || h <= 0 || maxval <= 0 || maxval > 255) {
    if (err) *err = path + ": not a binary 8-bit PGM (P5, maxval <= 255)";
    return false;
  }
  in.get();  // the single whitespace after maxval
  f.width = w;
  f.height = h;
  f.pixels.resize(static_cast<size_t>(w) * h);
  if (!in.read(reinterpret_cast<char*>(f.pixels.data()), static_cast<std::streamsize>(f.pixels.size()))) {
    if (err) *err = path + ": truncated pixel data";
    return false;
  }
  f.name = std::filesystem::path(path).filename().string();
  return true;
}

std::vector<std::string> listPgm(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return out;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    if (e.is_regular_file() && e.path().extension() == ".pgm") out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace gpu_test
}  // namespace hapi_frontend
