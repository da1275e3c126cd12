// The motion model, the IMU and the first pose's uncertainty, one part of
// the settings (settings.hpp composes them): the motion models
// (motion_model.hpp), the pose kinematics, the inertial alignment and the
// scene-motion monitor read it. Declared once in motion_settings.def.
#pragma once

#include "hapi_eskf/field_table.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {

// The motion model of the pose block (motion_model.hpp).
enum class MotionModelKind { kConstantVelocity, kGyro, kInertial };

template <>
struct EnumNames<MotionModelKind> {
  static constexpr EnumName<MotionModelKind> kNames[] = {{MotionModelKind::kConstantVelocity, "constant_velocity"},
                                                         {MotionModelKind::kGyro, "gyro"},
                                                         {MotionModelKind::kInertial, "inertial"}};
};
inline const char* toString(MotionModelKind m) { return enumToString(m); }

struct MotionSettings {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/backend/motion_settings.def"
#undef HAPI_FIELD
};

HAPI_SETTINGS_VISITOR(MotionSettings) {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_eskf/backend/motion_settings.def"
#undef HAPI_FIELD
}

}  // namespace hapi_eskf
