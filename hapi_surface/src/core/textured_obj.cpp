#include "hapi_surface/textured_obj.hpp"

#include "hapi_surface/png_io.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>

namespace hapi_surface {
namespace {

// The colour at barycentric (a, b) of a triangle's corner colours (c0 at
// (0, 0), c1 at a = 1, c2 at b = 1), clamped to the triangle.
Rgb8 blend(const Rgb8& c0, const Rgb8& c1, const Rgb8& c2, double a, double b) {
  if (a + b > 1) {
    const double s = a + b;
    a /= s;
    b /= s;
  }
  Rgb8 out;
  for (int k = 0; k < 3; ++k)
    out[k] = static_cast<std::uint8_t>(std::lround((1 - a - b) * c0[k] + a * c1[k] + b * c2[k]));
  return out;
}

std::string stem(const std::string& path) { return path.substr(0, path.size() - 4); }

std::string baseName(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

bool writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return static_cast<bool>(f);
}

std::string objText(const Mesh& mesh, const TextureAtlas& atlas, const std::string& mtl_name) {
  std::string s = "# hapi_surface: the skin surface, its projected values as the texture\nmtllib " + mtl_name + "\n";
  char line[128];
  for (const auto& v : mesh.vertices) {
    std::snprintf(line, sizeof line, "v %.7g %.7g %.7g\n", v.x(), v.y(), v.z());
    s += line;
  }
  const bool normals = mesh.normals.size() == mesh.vertices.size();
  for (std::size_t i = 0; normals && i < mesh.normals.size(); ++i) {
    const auto& n = mesh.normals[i];
    std::snprintf(line, sizeof line, "vn %.6g %.6g %.6g\n", n.x(), n.y(), n.z());
    s += line;
  }
  for (const auto& t : atlas.uv)
    for (const auto& c : t) {
      std::snprintf(line, sizeof line, "vt %.8g %.8g\n", c.x(), c.y());
      s += line;
    }
  s += "usemtl surface\n";
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    s += "f";
    for (int k = 0; k < 3; ++k) {
      const long v = mesh.faces[f][k] + 1, t = static_cast<long>(3 * f + k + 1);
      if (normals) std::snprintf(line, sizeof line, " %ld/%ld/%ld", v, t, v);
      else std::snprintf(line, sizeof line, " %ld/%ld", v, t);
      s += line;
    }
    s += "\n";
  }
  return s;
}

}  // namespace

TextureAtlas buildTextureAtlas(const Mesh& mesh, const std::vector<Rgb8>& colours, int cell) {
  TextureAtlas a;
  const std::size_t n = mesh.faces.size();
  if (n == 0 || cell < 2) return a;
  const int cols = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  const int rows = static_cast<int>((n + cols - 1) / cols);
  a.width = cols * cell;
  a.height = rows * cell;
  a.texels.assign(static_cast<std::size_t>(a.width) * a.height, Rgb8{128, 128, 128});
  a.uv.resize(n);
  const double last = cell - 1;
  for (std::size_t f = 0; f < n; ++f) {
    const int x0 = static_cast<int>(f % cols) * cell, y0 = static_cast<int>(f / cols) * cell;
    const auto& tri = mesh.faces[f];
    for (int j = 0; j < cell; ++j)
      for (int i = 0; i < cell; ++i)
        a.texels[static_cast<std::size_t>(y0 + j) * a.width + x0 + i] =
            blend(colours[tri[0]], colours[tri[1]], colours[tri[2]], i / last, j / last);
    // Texel centres; OBJ's v runs up from the image's bottom row.
    auto uv = [&](double x, double y) {
      return Eigen::Vector2f(static_cast<float>((x + 0.5) / a.width), static_cast<float>(1.0 - (y + 0.5) / a.height));
    };
    a.uv[f] = {uv(x0, y0), uv(x0 + last, y0), uv(x0, y0 + last)};
  }
  return a;
}

bool isObjPath(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".obj";
}

SurfaceStatus writeTexturedObj(const std::string& obj_path, const Mesh& mesh, const std::vector<Rgb8>& colours,
                               int cell) {
  if (mesh.empty()) return SurfaceStatus::kNoVolume;
  if (colours.size() != mesh.vertices.size()) return SurfaceStatus::kSizeMismatch;
  if (!isObjPath(obj_path)) return SurfaceStatus::kIoError;
  const TextureAtlas atlas = buildTextureAtlas(mesh, colours, cell);
  const std::string base = stem(obj_path), name = baseName(base);
  const std::string mtl = "# hapi_surface\nnewmtl surface\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nd 1\nillum 1\nmap_Kd " +
                          name + ".png\n";
  const bool ok = writeFile(base + ".png", pngBytes(atlas.width, atlas.height, atlas.texels)) &&
                  writeFile(base + ".mtl", mtl) && writeFile(obj_path, objText(mesh, atlas, name + ".mtl"));
  return ok ? SurfaceStatus::kOk : SurfaceStatus::kIoError;
}

}  // namespace hapi_surface
