// The rules a map's content must meet (docs/DESIGN.md "Map file"), one copy
// for the writer (it refuses to save a map that a reader would refuse) and
// the reader: finite numbers, metres, unit gravity or none, a plausible
// calibration, unique ids, positive definite covariances, descriptors of
// the map's type and length; and whether the map was made with the running
// camera.
#pragma once

#include "hapi_eskf/map_file/map_data.hpp"
#include "hapi_eskf/map_file/map_error.hpp"

namespace hapi_eskf {
namespace map_file {

// Relative difference of intrinsics or baseline above which two calibrations
// are different cameras (a re-calibration of the same rig stays well below
// 1 %: the chessboard test's 3 % focal error is a wrong calibration).
constexpr double kCalibrationTolerance = 0.01;
// Largest |R^T R - I| and |p| difference [m] of two T_imu_cam that are one mount.
constexpr double kExtrinsicRotationTolerance = 1e-2;
constexpr double kExtrinsicTranslationTolerance = 5e-3;

MapError checkCalibration(const MapCalibration& c);
MapError checkLandmark(const MapLandmark& l, uint32_t descriptor_length, std::size_t index);
// A keyframe: id > 0, a rotation, finite numbers, positive definite
// covariances, descriptors of the map's length.
MapError checkKeyframe(const Keyframe& k, uint32_t descriptor_length, std::size_t index);
// Everything of the map (the landmarks' ids unique among them, the
// keyframes' among them).
MapError checkMapData(const MapData& map);
// kCalibrationMismatch naming the first field that differs.
MapError checkSameCamera(const MapCalibration& map, const MapCalibration& running);

}  // namespace map_file
}  // namespace hapi_eskf
