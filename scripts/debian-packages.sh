# Debian bookworm packages needed to build, run and test everything.
# Sourced by scripts/setup.sh; one list so the README and CI cannot drift.
HAPI_DEBIAN_PACKAGES=(
  build-essential cmake git
  catkin catkin-lint ros-core-dev rosbash python3-roslaunch
  libnodeletlib-dev libnodeletlib-tools python3-nodelet
  libtf2-ros-dev libtf2-geometry-msgs-dev libtf2-eigen-dev python3-tf2-ros
  libimage-transport-dev image-transport-tools libcv-bridge-dev libimage-geometry-dev
  libmessage-filters-dev librosbag-dev python3-rosbag
  librostest-dev python3-rostest
  python3-rosdep2  # offline rosdep view for rospkg-based tools (scripts/rosdep_offline.sh)
  libsensor-msgs-dev libnav-msgs-dev libgeometry-msgs-dev libdiagnostic-msgs-dev
  libstd-srvs-dev python3-std-srvs libdiagnostic-updater-dev python3-diagnostic-updater
  libopencv-dev libeigen3-dev libgtest-dev googletest
  xplanet-images python3-numpy python3-yaml
  python3-matplotlib  # tools/eval plots (PNG)
  # docs/CALIBRATION.md: cameracalibrator.py; its solver in test/system (the Python module's
  # imports, which its Debian package does not declare: cv_bridge, image_geometry)
  ros-camera-calibration python3-camera-calibration python3-cv-bridge python3-image-geometry
  python3-opencv  # tools/eval/motion_study.py: OpenCV's optical flow baselines (Farneback, DIS, pyramidal LK)
  libopenblas-dev  # hapi_eskf CPU backend: rank update and factorisations on OpenBLAS/LAPACK (cpu_linear_algebra.cpp)
  libmrpt-dev  # hapi_eskf_mrpt_bench: MRPT's EKF update side by side with the CPU backend (bench only, optional)
  libceres-dev  # hapi_eskf Graph SLAM and graph_refine (src/graph; skipped without it)
  iproute2 iptables iputils-ping procps
  clang-14 libfuzzer-14-dev libclang-rt-14-dev  # test/fuzz: libFuzzer targets (clang, ASan+UBSan runtimes)
  # system: evaluator/ground-truth nodes (Python messages), rviz under Xvfb + xwd screenshots
  python3-sensor-msgs python3-nav-msgs rviz xvfb x11-apps x11-utils
)
