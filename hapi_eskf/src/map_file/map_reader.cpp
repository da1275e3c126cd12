// Map file decoding and checking (map_reader.hpp; layout in map_format.hpp).
#include "hapi_eskf/map_file/map_reader.hpp"

#include "byte_io.hpp"
#include "hapi_eskf/map_file/map_checks.hpp"
#include "hapi_eskf/map_file/map_format.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

namespace hapi_eskf {
namespace map_file {
namespace {

struct Section {
  uint32_t type = 0, flags = 0;
  uint64_t offset = 0, size = 0;
};

std::string sectionName(uint32_t type) { return "section " + std::to_string(type); }

MapError shortSection(uint32_t type) {
  return mapError(MapFault::kBadSize, sectionName(type) + " is shorter than its content");
}

// Header and table: fills `sections` with the known ones (by type), checked
// to lie inside the file without overlapping each other or the table.
MapError readTable(const uint8_t* data, std::size_t size, std::vector<Section>* sections) {
  if (size < sizeof(kMagic)) return mapError(MapFault::kTruncated, "file of " + std::to_string(size) + " bytes");
  if (std::memcmp(data, kMagic, sizeof(kMagic)) != 0) return mapError(MapFault::kMagic, "not a HAPI map file");
  ByteReader r(data + sizeof(kMagic), size - sizeof(kMagic));
  uint32_t version, count;
  if (!r.u32(&version) || !r.u32(&count)) return mapError(MapFault::kTruncated, "header");
  if (version != kVersion)
    return mapError(MapFault::kVersion, "format version " + std::to_string(version) + ", this reader reads " +
                                            std::to_string(kVersion));
  if (count == 0 || count > kMaxSections)
    return mapError(MapFault::kSectionTable, std::to_string(count) + " sections (1.." +
                                                 std::to_string(kMaxSections) + ")");
  const uint64_t payload_begin = kHeaderBytes + uint64_t(count) * kSectionEntryBytes;
  std::vector<Section> all(count);
  for (Section& s : all)
    if (!r.u32(&s.type) || !r.u32(&s.flags) || !r.u64(&s.offset) || !r.u64(&s.size))
      return mapError(MapFault::kTruncated, "section table");
  std::sort(all.begin(), all.end(), [](const Section& a, const Section& b) { return a.offset < b.offset; });
  uint64_t end_of_previous = payload_begin;
  for (const Section& s : all) {
    if (s.offset < end_of_previous)
      return mapError(MapFault::kSectionTable, sectionName(s.type) + " overlaps the table or another section");
    if (s.size > size || s.offset > size - s.size)
      return mapError(MapFault::kTruncated, sectionName(s.type) + " ends past the file's " +
                                                std::to_string(size) + " bytes");
    end_of_previous = s.offset + s.size;
    const bool known = s.type >= kSectionMeta && s.type <= kSectionKeyframes;
    if (!known && (s.flags & kSectionRequired))
      return mapError(MapFault::kSectionTable, "required " + sectionName(s.type) + " unknown to this reader");
    if (!known) continue;  // a later version's optional section
    for (const Section& seen : *sections)
      if (seen.type == s.type) return mapError(MapFault::kSectionTable, sectionName(s.type) + " twice");
    sections->push_back(s);
  }
  return {};
}

MapError readMeta(ByteReader r, MapData* map) {
  uint8_t unit;
  if (!r.u8(&unit) || !r.name(&map->map_frame, kMaxNameBytes) || !r.name(&map->camera_frame, kMaxNameBytes))
    return mapError(MapFault::kBadSize, "meta section's unit or frame names (longer than " +
                                            std::to_string(kMaxNameBytes) + " bytes, or cut)");
  if (unit != kUnitMetre) return mapError(MapFault::kUnit, "length unit code " + std::to_string(unit));
  for (int i = 0; i < 3; ++i)
    if (!r.f64(&map->gravity_direction[i])) return shortSection(kSectionMeta);
  if (!r.f64(&map->created)) return shortSection(kSectionMeta);
  if (r.left() != 0) return mapError(MapFault::kBadSize, "meta section has trailing bytes");
  return {};
}

MapError readCalibration(ByteReader r, MapCalibration* c) {
  uint8_t has_imu;
  bool ok = r.u32(&c->width) && r.u32(&c->height);
  for (double* v : {&c->fx, &c->fy, &c->cx, &c->cy, &c->baseline}) ok = ok && r.f64(v);
  ok = ok && r.u8(&has_imu);
  for (int k = 0; k < 9; ++k) ok = ok && r.f64(&c->imu_cam.R_imu_cam(k / 3, k % 3));
  for (int i = 0; i < 3; ++i) ok = ok && r.f64(&c->imu_cam.p_imu_cam[i]);
  if (!ok) return shortSection(kSectionCalibration);
  if (has_imu > 1) return mapError(MapFault::kBadValue, "calibration has_imu " + std::to_string(has_imu));
  c->has_imu = has_imu == 1;
  if (r.left() != 0) return mapError(MapFault::kBadSize, "calibration section has trailing bytes");
  return {};
}

template <int N>
bool readUpperTriangle(ByteReader* r, Eigen::Matrix<double, N, N>* C) {
  for (int row = 0; row < N; ++row)
    for (int k = row; k < N; ++k) {
      double v;
      if (!r->f64(&v)) return false;
      (*C)(row, k) = (*C)(k, row) = v;
    }
  return true;
}

MapError readLandmarks(ByteReader r, MapData* map) {
  uint64_t count;
  if (!r.u8(&map->descriptor_type) || !r.u32(&map->descriptor_length) || !r.u64(&count))
    return shortSection(kSectionLandmarks);
  const uint32_t expected = descriptorLengthOf(map->descriptor_type);
  if (expected == 0 || map->descriptor_length != expected)
    return mapError(MapFault::kDescriptorType, "descriptor type " + std::to_string(map->descriptor_type) +
                                                   " with length " + std::to_string(map->descriptor_length));
  const uint64_t record = kLandmarkFixedBytes + uint64_t(map->descriptor_length);
  if (count > r.left() / record || count * record != r.left())
    return mapError(MapFault::kBadSize, std::to_string(count) + " landmarks of " + std::to_string(record) +
                                            " bytes in " + std::to_string(r.left()) + " bytes");
  map->landmarks.resize(count);
  for (MapLandmark& l : map->landmarks) {
    bool ok = r.u64(&l.id);
    for (int i = 0; i < 3; ++i) ok = ok && r.f64(&l.position[i]);
    ok = ok && readUpperTriangle(&r, &l.covariance);
    ok = ok && r.u32(&l.times_observed);
    l.descriptor.resize(map->descriptor_length);
    ok = ok && r.raw(l.descriptor.data(), l.descriptor.size());
    if (!ok) return shortSection(kSectionLandmarks);  // unreachable after the size check
  }
  return {};
}

// After the landmarks: the points' descriptors have the landmarks' length.
MapError readKeyframes(ByteReader r, MapData* map) {
  uint64_t count;
  if (!r.u64(&count)) return shortSection(kSectionKeyframes);
  if (count > r.left() / kKeyframeFixedBytes)
    return mapError(MapFault::kBadSize, std::to_string(count) + " keyframes in " + std::to_string(r.left()) + " bytes");
  const uint64_t point_bytes = kKeyframePointFixedBytes + uint64_t(map->descriptor_length);
  map->keyframes.resize(count);
  for (Keyframe& k : map->keyframes) {
    Mat3 R;
    Vec3 p;
    uint32_t n = 0;
    bool ok = r.u64(&k.id) && r.f64(&k.stamp);
    for (int i = 0; i < 9; ++i) ok = ok && r.f64(&R(i / 3, i % 3));
    for (int i = 0; i < 3; ++i) ok = ok && r.f64(&p[i]);
    ok = ok && readUpperTriangle(&r, &k.pose_covariance) && r.u32(&n);
    if (!ok) return shortSection(kSectionKeyframes);
    if (n > r.left() / point_bytes) return shortSection(kSectionKeyframes);
    k.T_map_cam.linear() = R;
    k.T_map_cam.translation() = p;
    k.descriptor_length = static_cast<int>(map->descriptor_length);
    k.points.resize(n);
    k.point_covariances.resize(n);
    k.descriptors.resize(std::size_t{n} * map->descriptor_length);
    for (uint32_t i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) ok = ok && r.f64(&k.points[i][a]);
      ok = ok && readUpperTriangle(&r, &k.point_covariances[i]) &&
           r.raw(k.descriptors.data() + std::size_t{i} * map->descriptor_length, map->descriptor_length);
    }
    if (!ok) return shortSection(kSectionKeyframes);  // unreachable after the size check
  }
  if (r.left() != 0) return mapError(MapFault::kBadSize, "keyframes section has trailing bytes");
  return {};
}

MapError readSection(const uint8_t* data, const Section& s, MapData* map) {
  const ByteReader r(data + s.offset, s.size);
  switch (s.type) {
    case kSectionMeta: return readMeta(r, map);
    case kSectionCalibration: return readCalibration(r, &map->calibration);
    case kSectionLandmarks: return readLandmarks(r, map);
    case kSectionKeyframes: return readKeyframes(r, map);
    default: return {};
  }
}

}  // namespace

MapError decodeMap(const uint8_t* data, std::size_t size, const MapExpectation& expect, MapData* out) {
  std::vector<Section> sections;
  if (MapError e = readTable(data, size, &sections)) return e;
  for (uint32_t type : {kSectionMeta, kSectionCalibration, kSectionLandmarks}) {
    const bool present = std::any_of(sections.begin(), sections.end(), [&](const Section& s) { return s.type == type; });
    if (!present) return mapError(MapFault::kMissingSection, sectionName(type) + " absent");
  }
  // By type: the keyframes need the landmarks' descriptor length.
  std::sort(sections.begin(), sections.end(), [](const Section& a, const Section& b) { return a.type < b.type; });
  MapData map;
  for (const Section& s : sections)
    if (MapError e = readSection(data, s, &map)) return e;
  if (MapError e = checkMapData(map)) return e;
  if (expect.descriptor_type >= 0 && map.descriptor_type != expect.descriptor_type)
    return mapError(MapFault::kDescriptorType, "map's descriptor type " + std::to_string(map.descriptor_type) +
                                                   ", the front end's " + std::to_string(expect.descriptor_type));
  if (expect.calibration)
    if (MapError e = checkSameCamera(map.calibration, *expect.calibration)) return e;
  *out = std::move(map);
  return {};
}

MapError readMapFile(const std::string& path, const MapExpectation& expect, MapData* out) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return mapError(MapFault::kIo, "cannot open " + path + ": " + std::strerror(errno));
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (f.bad()) return mapError(MapFault::kIo, "read of " + path + " failed");
  return decodeMap(bytes.data(), bytes.size(), expect, out);
}

}  // namespace map_file
}  // namespace hapi_eskf
