#!/usr/bin/python3
"""rostest node: the running system's outputs, checked while a bag plays.

  * TF: map -> camera frame (the filter's REP-105 transform) can be looked up;
  * the landmark map (/eskf/map, PointCloud2) is non-empty, finite, has x y z
    and rgb fields and is in the map frame;
  * /eskf/pose (PoseWithCovarianceStamped) arrives in the map frame with a
    finite, symmetric, positive semi-definite 6x6 covariance;
  * /eskf/path grows.
Parameters (~): map_frame (map), camera_frame (stereo_left_optical_frame),
timeout (wall seconds per check, default 60).
"""
import math
import sys
import time
import unittest

import numpy as np
import rospy
import tf2_ros
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Path
from sensor_msgs import point_cloud2
from sensor_msgs.msg import PointCloud2


def wait_for(predicate, timeout):
    end = time.time() + timeout
    while time.time() < end and not rospy.is_shutdown():
        if predicate():
            return True
        time.sleep(0.1)
    return predicate()


class LiveChecks(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("hapi_live_checks")
        cls.map_frame = rospy.get_param("~map_frame", "map")
        cls.camera_frame = rospy.get_param("~camera_frame", "stereo_left_optical_frame")
        cls.timeout = float(rospy.get_param("~timeout", 60.0))
        cls.buffer = tf2_ros.Buffer(cache_time=rospy.Duration(60))
        cls.listener = tf2_ros.TransformListener(cls.buffer)
        cls.maps, cls.poses, cls.paths = [], [], []
        rospy.Subscriber("/eskf/map", PointCloud2, cls.maps.append, queue_size=2)
        rospy.Subscriber("/eskf/pose", PoseWithCovarianceStamped, cls.poses.append, queue_size=50)
        rospy.Subscriber("/eskf/path", Path, cls.paths.append, queue_size=5)

    def test_1_tf_map_to_camera(self):
        def ok():
            try:
                self.buffer.lookup_transform(self.map_frame, self.camera_frame, rospy.Time(0))
                return True
            except (tf2_ros.LookupException, tf2_ros.ConnectivityException, tf2_ros.ExtrapolationException):
                return False
        self.assertTrue(wait_for(ok, self.timeout),
                        f"no TF {self.map_frame} -> {self.camera_frame} within {self.timeout} s")
        t = self.buffer.lookup_transform(self.map_frame, self.camera_frame, rospy.Time(0)).transform
        q = [t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w]
        self.assertAlmostEqual(math.sqrt(sum(v * v for v in q)), 1.0, places=6)

    def test_2_map_non_empty(self):
        def non_empty():
            return any(m.width * m.height > 0 for m in list(self.maps))
        self.assertTrue(wait_for(non_empty, self.timeout), f"/eskf/map empty or absent after {self.timeout} s")
        m = [m for m in list(self.maps) if m.width * m.height > 0][-1]
        self.assertEqual(m.header.frame_id, self.map_frame)
        names = {f.name for f in m.fields}
        self.assertTrue({"x", "y", "z", "rgb"} <= names, f"map fields {sorted(names)}")
        pts = np.array(list(point_cloud2.read_points(m, ("x", "y", "z"))), dtype=float)
        self.assertGreater(len(pts), 0)
        self.assertTrue(np.all(np.isfinite(pts)), "non-finite map points")

    def test_3_pose_with_covariance(self):
        self.assertTrue(wait_for(lambda: len(self.poses) > 0, self.timeout), "no /eskf/pose")
        p = self.poses[-1]
        self.assertEqual(p.header.frame_id, self.map_frame)
        c = np.array(p.pose.covariance).reshape(6, 6)
        self.assertTrue(np.all(np.isfinite(c)))
        self.assertTrue(np.allclose(c, c.T, atol=1e-9), "covariance not symmetric")
        self.assertGreaterEqual(np.linalg.eigvalsh(c).min(), -1e-9, "covariance not PSD")

    def test_4_path_grows(self):
        self.assertTrue(wait_for(lambda: len(self.paths) > 0, self.timeout), "no /eskf/path")
        n0 = len(self.paths[-1].poses)
        self.assertTrue(wait_for(lambda: len(self.paths[-1].poses) > n0, self.timeout), "path does not grow")


if __name__ == "__main__":
    import rostest
    rostest.rosrun("hapi_slam", "live_checks", LiveChecks, sys.argv)
