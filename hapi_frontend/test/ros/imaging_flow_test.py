#!/usr/bin/env python3
"""rostest node (imaging_flow.test): feeds ImagingFlowNodelet a band-limited
texture (a sum of plane waves, so sub-pixel shifts are exact) moving by a
known flow, plus bad images, and checks ~flow and /diagnostics. Each image is
sent once the previous one's outcome is seen (a flow message or a counter),
so a slow machine cannot merge or drop frames."""
import math
import threading
import time
import unittest

import numpy as np
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from hapi_msgs.msg import ImageFlow
from sensor_msgs.msg import Image

W, H = 320, 200
STEP = (0.6, -0.35)  # [px/frame]
U, V = 150.0, 90.0


def texture(dx, dy):
    rng = np.random.default_rng(3)
    y, x = np.mgrid[0:H, 0:W].astype(float)
    img = np.full((H, W), 128.0)
    for _ in range(40):
        a, p = rng.uniform(0, 2 * math.pi, 2)
        k = 2 * math.pi / rng.uniform(5, 40)
        img += 100.0 / math.sqrt(20) / 3 * np.sin(k * math.cos(a) * (x - dx) + k * math.sin(a) * (y - dy) + p)
    return np.clip(np.round(img), 0, 255).astype(np.uint8)


def image(t, pixels, encoding="mono8", frame="imaging_optical_frame"):
    m = Image()
    m.header.stamp, m.header.frame_id = rospy.Time.from_sec(t), frame
    m.height, m.width = pixels.shape[:2]
    m.encoding = encoding
    m.step = m.width * pixels.dtype.itemsize * (pixels.shape[2] if pixels.ndim == 3 else 1)
    m.data = pixels.tobytes()
    return m


class ImagingFlowTest(unittest.TestCase):
    def setUp(self):
        rospy.init_node("imaging_flow_test", anonymous=True)
        self.lock = threading.Lock()
        self.flows = []
        self.diag = {}
        self.pub = rospy.Publisher("/imaging/image_raw", Image, queue_size=10)
        rospy.Subscriber("/imaging_flow/flow", ImageFlow, self.on_flow, queue_size=50)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag, queue_size=50)

    def on_flow(self, m):
        with self.lock:
            self.flows.append(m)

    def on_diag(self, a):
        with self.lock:
            for s in a.status:
                self.diag[s.name] = s

    @staticmethod
    def wait(predicate, timeout=15.0):
        deadline = time.time() + timeout
        while not predicate():
            if time.time() > deadline or rospy.is_shutdown():
                return False
            time.sleep(0.02)
        return True

    def counter(self, key):
        with self.lock:
            for name, s in self.diag.items():
                if name.startswith("imaging_flow:"):
                    for kv in s.values:
                        if kv.key == key:
                            return int(kv.value)
        return 0

    def send_expect_flow(self, msg):
        n = len(self.flows)
        self.pub.publish(msg)
        self.assertTrue(self.wait(lambda: len(self.flows) > n), "no flow for the image at %s" % msg.header.stamp)
        return self.flows[-1]

    def send_expect_count(self, msg, key):
        before = self.counter(key)
        self.pub.publish(msg)
        self.assertTrue(self.wait(lambda: self.counter(key) > before), "%s not counted" % key)

    def test_flow_restarts_and_bad_images(self):
        deadline = time.time() + 30
        while self.pub.get_num_connections() == 0 and time.time() < deadline:
            time.sleep(0.1)
        self.assertGreater(self.pub.get_num_connections(), 0, "the nodelet did not subscribe")
        t = 100.0
        first = self.send_expect_flow(image(t, texture(0, 0)))
        self.assertEqual(first.status, ImageFlow.STATUS_FIRST_FRAME)
        for k in range(1, 5):
            t += 0.025
            f = self.send_expect_flow(image(t, texture(STEP[0] * k, STEP[1] * k)))
            self.assertEqual(f.status, ImageFlow.STATUS_OK)
            self.assertEqual(f.header.frame_id, "imaging_optical_frame")
            self.assertAlmostEqual(f.previous_stamp.to_sec(), t - 0.025, places=6)
            self.assertAlmostEqual(f.u, U)
            self.assertAlmostEqual(f.v, V)
            self.assertAlmostEqual(f.affine[0], STEP[0], delta=0.03)
            self.assertAlmostEqual(f.affine[1], STEP[1], delta=0.03)
            self.assertGreater(f.affine_covariance[0], 0.0)
            self.assertGreaterEqual(f.tracked, f.inliers)
            self.assertGreaterEqual(f.inliers, 10)
        # A stamp going back restarts.
        f = self.send_expect_flow(image(t - 1.0, texture(0, 0)))
        self.assertEqual(f.status, ImageFlow.STATUS_FIRST_FRAME)
        # Bad images are counted, the nodelet keeps running.
        self.send_expect_count(image(t + 1, np.zeros((H, W, 2), np.uint8), "yuv422"), "rejected.unsupported_encoding")
        self.send_expect_count(image(t + 1, texture(0, 0), frame=""), "rejected.missing_frame_id")
        truncated = image(t + 1, texture(0, 0))
        truncated.data = truncated.data[:100]
        self.send_expect_count(truncated, "rejected.malformed_image")
        f = self.send_expect_flow(image(t - 0.975, texture(STEP[0], STEP[1])))
        self.assertEqual(f.status, ImageFlow.STATUS_OK)
        self.assertAlmostEqual(f.affine[0], STEP[0], delta=0.03)
        self.assertTrue(self.wait(lambda: self.counter("restart.stamp_not_increasing") >= 1))
        # The instance with invalid parameters refuses to run.
        self.assertTrue(self.wait(lambda: any(n.startswith("imaging_flow_invalid") and
                                              s.level == DiagnosticStatus.ERROR for n, s in self.diag.items())),
                        "imaging_flow_invalid did not report ERROR")


if __name__ == "__main__":
    rostest.rosrun("hapi_frontend", "imaging_flow", ImagingFlowTest)
