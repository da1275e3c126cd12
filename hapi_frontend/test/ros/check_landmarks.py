#!/usr/bin/env python3
"""rostest node: checks the content of every hapi_msgs/StereoLandmarks message
published by the front end while the globe bag plays (see frontend_globe.test).

Per message: >= ~min_landmarks landmarks, ids 0..N-1, descriptor bytes =
N * descriptor_length (32 for ORB), finite positions in front of the camera
within the depth range whose projection with the left camera_info of that
stamp lies inside the image, symmetric positive-definite covariances,
header.frame_id = the left optical frame, header.stamp equal to the stamp of
a left image that was published.
Over the run: a landmarks message for >= ~min_frame_fraction of the left
images between the first and the last message (counted in frames, the bag's
time, not in wall-clock Hz).
"""
import math
import sys
import threading
import unittest

import numpy as np
import rospy
import rostest
from hapi_msgs.msg import StereoLandmarks
from sensor_msgs.msg import CameraInfo, Image


class LandmarksContentTest(unittest.TestCase):
    def setUp(self):
        rospy.init_node("check_landmarks", anonymous=True)
        self.lock = threading.Lock()
        self.msgs = []
        self.image_stamps = set()
        self.infos = {}
        self.frame_id = rospy.get_param("~frame_id")
        self.min_landmarks = rospy.get_param("~min_landmarks", 150)
        self.min_messages = rospy.get_param("~min_messages", 20)
        self.timeout = rospy.get_param("~timeout", 60.0)
        self.min_frame_fraction = rospy.get_param("~min_frame_fraction", 0.5)
        rospy.Subscriber(rospy.get_param("~image_topic"), Image, self.on_image, queue_size=100)
        rospy.Subscriber(rospy.get_param("~info_topic"), CameraInfo, self.on_info, queue_size=100)
        rospy.Subscriber(rospy.get_param("~topic"), StereoLandmarks, self.on_landmarks, queue_size=100)

    def on_image(self, m):
        with self.lock:
            self.image_stamps.add(m.header.stamp.to_nsec())

    def on_info(self, m):
        with self.lock:
            self.infos[m.header.stamp.to_nsec()] = m

    def on_landmarks(self, m):
        with self.lock:
            self.msgs.append(m)

    def check_message(self, m):
        n = len(m.landmarks)
        self.assertGreaterEqual(n, self.min_landmarks)
        self.assertEqual(m.header.frame_id, self.frame_id)
        self.assertIn(m.header.stamp.to_nsec(), self.image_stamps, "stamp is not a left image stamp")
        self.assertEqual(m.descriptor_type, StereoLandmarks.DESCRIPTOR_ORB)
        self.assertEqual(m.descriptor_length, 32)
        self.assertEqual(len(m.descriptors), n * m.descriptor_length)
        self.assertGreater(len(set(bytes(m.descriptors[i * 32:(i + 1) * 32]) for i in range(n))), n // 2,
                           "descriptors look constant")
        self.assertEqual([l.id for l in m.landmarks], list(range(n)))
        info = self.infos.get(m.header.stamp.to_nsec())
        self.assertIsNotNone(info, "no camera_info seen with the landmarks stamp")
        K = np.array(info.K).reshape(3, 3)
        w, h = info.width, info.height
        prev_response = math.inf
        for l in m.landmarks:
            p = np.array([l.position.x, l.position.y, l.position.z])
            self.assertTrue(np.all(np.isfinite(p)))
            self.assertGreater(p[2], 0.0, "landmark behind the camera")
            self.assertLess(p[2], 20.0)
            C = np.array(l.position_covariance).reshape(3, 3)
            self.assertTrue(np.all(np.isfinite(C)))
            self.assertTrue(np.allclose(C, C.T, rtol=1e-9, atol=1e-15), "covariance not symmetric")
            self.assertGreater(np.linalg.eigvalsh(C).min(), 0.0, "covariance not positive definite")
            # Undistorted keypoint re-projected with K: inside the image up to
            # what undistortion moves a border pixel.
            u, v = (K @ p)[:2] / p[2]
            self.assertTrue(-0.05 * w <= u <= 1.05 * w and -0.05 * h <= v <= 1.05 * h, (u, v))
            self.assertLessEqual(l.response, prev_response, "landmarks not sorted by response")
            prev_response = l.response

    def test_content(self):
        deadline = rospy.Time.now() + rospy.Duration(self.timeout)
        while not rospy.is_shutdown() and rospy.Time.now() < deadline:
            with self.lock:
                if len(self.msgs) >= self.min_messages:
                    break
            rospy.sleep(0.1)
        rospy.sleep(0.5)  # let the image/info callbacks of the last stamps land
        with self.lock:
            msgs = list(self.msgs)
        self.assertGreaterEqual(len(msgs), self.min_messages, "too few landmark messages")
        counts = [len(m.landmarks) for m in msgs]
        rospy.loginfo("checked %d messages, landmarks per message min %d mean %.1f max %d",
                      len(msgs), min(counts), float(np.mean(counts)), max(counts))
        stamps = [m.header.stamp.to_nsec() for m in msgs]
        self.assertEqual(stamps, sorted(stamps), "stamps not increasing")
        with self.lock:
            images = sum(1 for t in self.image_stamps if stamps[0] <= t <= stamps[-1])
        rospy.loginfo("%d landmark messages for %d left images in the same span", len(set(stamps)), images)
        self.assertGreaterEqual(len(set(stamps)), self.min_frame_fraction * images,
                                "frames without landmarks: %d messages for %d images" % (len(set(stamps)), images))
        for m in msgs:
            with self.subTest(stamp=str(m.header.stamp)):
                self.check_message(m)


if __name__ == "__main__":
    rostest.rosrun("hapi_frontend", "landmarks_content", LandmarksContentTest, sys.argv)
