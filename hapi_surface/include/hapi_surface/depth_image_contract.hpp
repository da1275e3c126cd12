// The depth input of hapi_surface/SurfaceNodelet, as the dense stereo depth
// nodelet publishes it (one statement of the contract for both sides):
//
//  * kDepthTopic: sensor_msgs/Image, encoding kDepthEncoding (32FC1), depth
//    along the optical axis in metres; a pixel without depth is NaN
//    (REP-118: also +/-inf or 0, all read as "no measurement").
//  * kConfidenceTopic (optional): sensor_msgs/Image, same size and stamp,
//    the per-pixel weight of the depth (>= 0, finite where the depth is
//    valid; 0 = do not use): 32FC1, or mono8 / 8UC1 with
//    kConfidenceMono8One = a weight of 1 (the dense depth's, one byte a
//    pixel over the robot's link).
//  * kDepthInfoTopic: sensor_msgs/CameraInfo of the depth image: the
//    rectified left camera (K = the rectified projection's 3 x 3 part, no
//    distortion), the depth image's size.
//  * header.frame_id of all three: the rectified left camera's optical
//    frame (REP-103: z forward, x right, y down); header.stamp: the stamp of
//    the stereo pair the depth comes from, so TF gives the camera pose of
//    that instant.
#pragma once

namespace hapi_surface {

constexpr const char* kDepthTopic = "depth";
constexpr const char* kConfidenceTopic = "depth_confidence";
constexpr const char* kDepthInfoTopic = "depth_camera_info";
constexpr const char* kDepthEncoding = "32FC1";
constexpr double kConfidenceMono8One = 255.0;

}  // namespace hapi_surface
