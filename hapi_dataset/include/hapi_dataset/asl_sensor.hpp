// Sensor descriptions of an ASL/EuRoC recording (mav0/<sensor>/sensor.yaml)
// and of a Kalibr calibration (camchain-imucam.yaml):
// the body-frame extrinsic T_BS, and for cameras the pinhole intrinsics,
// radial-tangential distortion and resolution. Read with cv::FileStorage,
// which accepts EuRoC's "%YAML:1.0" files.
#pragma once

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace hapi_dataset {

// One camera of the rig as the dataset describes it (unrectified).
struct CameraSensor {
  Eigen::Isometry3d T_BS = Eigen::Isometry3d::Identity();  // camera pose in the body frame
  int width = 0, height = 0;                                  // [px]
  double fu = 0, fv = 0, cu = 0, cv = 0;                      // [px]
  std::vector<double> distortion;                             // k1 k2 p1 p2 (radial-tangential)
  double rate_hz = 0;
};

// The IMU: its pose in the body frame (identity in EuRoC, where body = IMU)
// and the noise densities the dataset states (0 when absent).
struct ImuSensor {
  Eigen::Isometry3d T_BS = Eigen::Isometry3d::Identity();
  double rate_hz = 0;
  double gyroscope_noise_density = 0;       // [rad/s/sqrt(Hz)]
  double gyroscope_random_walk = 0;         // [rad/s^2/sqrt(Hz)]
  double accelerometer_noise_density = 0;   // [m/s^2/sqrt(Hz)]
  double accelerometer_random_walk = 0;     // [m/s^3/sqrt(Hz)]
};

// Throw std::runtime_error naming the file and the field on anything missing
// or malformed (pinhole model and radial-tangential distortion only).
CameraSensor readCameraSensor(const std::string& sensor_yaml);
ImuSensor readImuSensor(const std::string& sensor_yaml);

// T_BS of a sensor.yaml (4x4 row-major "data" of 16 numbers, rigid).
Eigen::Isometry3d readBodyTransform(const std::string& sensor_yaml);

// A stereo camera + IMU calibrated by Kalibr (kalibr_calibrate_imu_camera's
// camchain-imucam.yaml, or kalibr_calibrate_cameras' camchain.yaml without
// the IMU): the same pinhole + radtan fields as sensor.yaml, each camera's
// T_BS its pose in cam0's frame (cam0: identity; cam1 from T_cn_cnm1).
struct KalibrCamchain {
  CameraSensor cam0, cam1;
  bool has_imu = false;                                         // cam0 has T_cam_imu
  Eigen::Isometry3d T_cam_imu = Eigen::Isometry3d::Identity();  // X_cam0 = T X_imu (~T_cam_imu)
  double timeshift_cam_imu = 0;  // [s] t_imu = t_cam + shift (imu_time_offset)
};
// Throws std::runtime_error like readCameraSensor.
KalibrCamchain readKalibrCamchain(const std::string& camchain_yaml);

}  // namespace hapi_dataset
