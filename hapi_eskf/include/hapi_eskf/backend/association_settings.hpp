// Association, gate and relocalisation after an outage, one part of the
// settings (settings.hpp composes them): association.hpp and relocaliser.hpp
// read it. Declared once in association_settings.def.
#pragma once

#include "hapi_eskf/field_table.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {

// Smallest RANSAC inlier set that may relocalise the pose (relocalise_gap):
// 12 pairs pin 6 dof with a wide margin against a chance fit of wrong matches.
constexpr int kRelocaliseMinInliers = 6;
// How long after an outage frames without such a fit are held back
// (prediction only: updating or adding landmarks at an unknown pose would
// corrupt the map) before the filter carries on without relocalising (the
// camera may look at unmapped ground only) [s].
constexpr double kRelocaliseWaitS = 2.0;
// Smallest inlier set that relocalises in a loaded map (Eskf::loadMap): no
// pose hint, the whole map is searched, so a chance fit of wrong matches on
// unmapped skin must be ruled out with a wider margin than after an outage.
constexpr int kMapRelocaliseMinInliers = 12;
// With gravity known (the inertial model), a map fit whose camera tilt
// disagrees with the IMU's by more than this (or 3 sigma of the filter's
// gravity, whichever is larger) is no relocalisation: wrong matches fit any
// tilt, the IMU levels the camera to well within a degree at rest.
constexpr double kMapRelocaliseMaxTilt = 0.1;  // [rad]

struct AssociationSettings {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/backend/association_settings.def"
#undef HAPI_FIELD
};

HAPI_SETTINGS_VISITOR(AssociationSettings) {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_eskf/backend/association_settings.def"
#undef HAPI_FIELD
}

}  // namespace hapi_eskf
