// Map file encoding (map_writer.hpp; layout in map_format.hpp).
#include "hapi_eskf/map_file/map_writer.hpp"

#include "byte_io.hpp"
#include "hapi_eskf/map_file/map_checks.hpp"
#include "hapi_eskf/map_file/map_format.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace hapi_eskf {
namespace map_file {
namespace {

void meta(const MapData& map, ByteWriter* w) {
  w->u8(kUnitMetre);
  w->name(map.map_frame);
  w->name(map.camera_frame);
  for (int i = 0; i < 3; ++i) w->f64(map.gravity_direction[i]);
  w->f64(map.created);
}

void calibration(const MapCalibration& c, ByteWriter* w) {
  w->u32(c.width);
  w->u32(c.height);
  for (double v : {c.fx, c.fy, c.cx, c.cy, c.baseline}) w->f64(v);
  w->u8(c.has_imu ? 1 : 0);
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) w->f64(c.imu_cam.R_imu_cam(r, k));
  for (int i = 0; i < 3; ++i) w->f64(c.imu_cam.p_imu_cam[i]);
}

// The upper triangle of the symmetrised matrix, row by row. A symmetric
// entry is written as it is, so it comes back bit for bit: halving the sum
// would overflow near the largest double and lose a subnormal's bit.
template <int N>
void upperTriangle(const Eigen::Matrix<double, N, N>& C, ByteWriter* w) {
  for (int r = 0; r < N; ++r)
    for (int k = r; k < N; ++k) {
      const double upper = C(r, k), lower = C(k, r);
      w->f64(upper == lower ? upper : 0.5 * upper + 0.5 * lower);
    }
}

void landmarks(const MapData& map, ByteWriter* w) {
  w->u8(map.descriptor_type);
  w->u32(map.descriptor_length);
  w->u64(map.landmarks.size());
  for (const MapLandmark& l : map.landmarks) {
    w->u64(l.id);
    for (int i = 0; i < 3; ++i) w->f64(l.position[i]);
    upperTriangle(l.covariance, w);
    w->u32(l.times_observed);
    w->raw(l.descriptor.data(), l.descriptor.size());
  }
}

void keyframes(const MapData& map, ByteWriter* w) {
  w->u64(map.keyframes.size());
  for (const Keyframe& k : map.keyframes) {
    w->u64(k.id);
    w->f64(k.stamp);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) w->f64(k.T_map_cam.linear()(r, c));
    for (int i = 0; i < 3; ++i) w->f64(k.T_map_cam.translation()[i]);
    upperTriangle(k.pose_covariance, w);
    w->u32(static_cast<uint32_t>(k.size()));
    for (std::size_t i = 0; i < k.size(); ++i) {
      for (int a = 0; a < 3; ++a) w->f64(k.points[i][a]);
      upperTriangle(k.point_covariances[i], w);
      w->raw(k.descriptor(i), static_cast<std::size_t>(k.descriptor_length));
    }
  }
}

}  // namespace

std::vector<uint8_t> encodeMap(const MapData& map, MapError* error) {
  *error = checkMapData(map);
  if (*error) return {};
  struct Section {
    uint32_t type, flags;
    void (*write)(const MapData&, ByteWriter*);
  };
  std::vector<Section> sections = {
      {kSectionMeta, kSectionRequired, meta},
      {kSectionCalibration, kSectionRequired,
       [](const MapData& m, ByteWriter* w) { calibration(m.calibration, w); }},
      {kSectionLandmarks, kSectionRequired, landmarks},
  };
  // Optional: a reader that does not know keyframes reads the rest.
  if (!map.keyframes.empty()) sections.push_back({kSectionKeyframes, 0, keyframes});
  const auto n = static_cast<uint32_t>(sections.size());
  ByteWriter w;
  w.raw(kMagic, sizeof(kMagic));
  w.u32(kVersion);
  w.u32(n);
  const std::size_t table = w.size();
  for (uint32_t i = 0; i < n; ++i) {
    w.u32(sections[i].type);
    w.u32(sections[i].flags);
    w.u64(0);  // offset, patched below
    w.u64(0);  // size
  }
  for (uint32_t i = 0; i < n; ++i) {
    const std::size_t begin = w.size();
    sections[i].write(map, &w);
    const std::size_t entry = table + i * kSectionEntryBytes;
    w.patchU64(entry + 8, begin);
    w.patchU64(entry + 16, w.size() - begin);
  }
  return std::move(w.bytes());
}

MapError writeMapFile(const std::string& path, const MapData& map) {
  MapError error;
  const std::vector<uint8_t> bytes = encodeMap(map, &error);
  if (error) return error;
  const std::string tmp = path + ".tmp";
  std::ofstream f(tmp, std::ios::binary);
  if (!f) return mapError(MapFault::kIo, "cannot open " + tmp + ": " + std::strerror(errno));
  f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  f.close();
  if (!f) return mapError(MapFault::kIo, "write to " + tmp + " failed");
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    return mapError(MapFault::kIo, "rename to " + path + ": " + std::strerror(errno));
  return {};
}

}  // namespace map_file
}  // namespace hapi_eskf
