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
// A placement on a map keyframe counts once the next frame's placement
// agrees with it: wrong matches on unmapped skin now and then fit some
// rigid motion, but two frames' chance fits do not land together. Agree:
// the camera moved between the two fits by no more than a hand moves it in
// that time plus the fits' own scatter.
constexpr double kKeyframeConfirmSpeed = 0.5;         // [m/s] a hand's fast motion
constexpr double kKeyframeConfirmRate = 1.0;          // [rad/s]
constexpr double kKeyframeConfirmTranslation = 0.01;  // [m] fit scatter
constexpr double kKeyframeConfirmRotation = 0.035;    // [rad] fit scatter (2 deg)

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
