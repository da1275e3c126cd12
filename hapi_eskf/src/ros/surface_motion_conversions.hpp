// Messages <-> the surface-motion estimator's plain types
// (hapi_eskf/surface_motion), for SurfaceMotionNodelet and its fuzz target.
#pragma once

#include "hapi_eskf/surface_motion/surface_motion_estimator.hpp"

#include <hapi_msgs/ImageFlow.h>
#include <hapi_msgs/SurfaceMotion.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/Marker.h>

#include <string>
#include <vector>

namespace hapi_eskf {
namespace ros_glue {

surface_motion::FlowMeasurement toFlowMeasurement(const hapi_msgs::ImageFlow& msg);

// The odometry's child frame's pose in its header frame and its twist (in
// the child frame, with the twist covariance).
surface_motion::CameraOdometry toCameraOdometry(const nav_msgs::Odometry& msg);

// K, plumb_bob D (or none) and the image size; `frame_rate` from the
// parameters. "" when usable, else why not (*out unchanged).
std::string toImagingCamera(const sensor_msgs::CameraInfo& msg, double frame_rate, surface_motion::ImagingCamera* out);

// The x y z fields of a PointCloud2 (FLOAT32 or FLOAT64); points with a
// non-finite coordinate are skipped. "" when read, else why not.
std::string toPoints(const sensor_msgs::PointCloud2& msg, std::vector<Vec3>* out);

hapi_msgs::SurfaceMotion toMessage(const surface_motion::SurfaceMotionOutput& out, const ros::Time& stamp,
                                   const std::string& frame);

// An ARROW from the skin point along the on-surface velocity (length
// marker_scale per mm/s); action DELETE when the output is not OK.
visualization_msgs::Marker toMarker(const hapi_msgs::SurfaceMotion& msg, double marker_scale);

}  // namespace ros_glue
}  // namespace hapi_eskf
