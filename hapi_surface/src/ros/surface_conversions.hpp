// Conversions between ROS messages and the surface core's plain types. Bad
// input is a status, never an exception.
#pragma once

#include "hapi_surface/colour_map.hpp"
#include "hapi_surface/float_image.hpp"
#include "hapi_surface/mesh.hpp"
#include "hapi_surface/pinhole_camera.hpp"

#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <visualization_msgs/Marker.h>

#include <string>
#include <vector>

namespace hapi_surface {
namespace ros_glue {

// The image's buffer as the core's view (no copy).
using hapi_nodelet_kit::rawView;

// A pinhole camera from K and the size; kBadCamera for zero or non-finite
// entries. Distortion is not modelled (D ignored): the depth image is
// rectified by contract, imaging frames are taken as pinhole.
SurfaceStatus toCamera(const sensor_msgs::CameraInfo& info, PinholeCamera* out);

// A TRIANGLE_LIST marker (every face's three corners, per-corner colours)
// in `frame`; empty points when the mesh is empty.
visualization_msgs::Marker toMarker(const Mesh& mesh, const std::vector<Rgb8>& colours, const std::string& frame,
                                    const ros::Time& stamp);

}  // namespace ros_glue
}  // namespace hapi_surface
