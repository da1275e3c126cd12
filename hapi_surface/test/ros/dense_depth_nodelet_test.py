#!/usr/bin/env python3
"""rostest node of dense_depth_nodelet.test: feeds DenseDepthNodelet a
synthetic raw pair (no distortion, R = I) of a fronto-parallel plane at
Z = 0.25 m, then malformed pairs, each sent once the previous one's outcome
is seen (its depth, or its rejection counted in /diagnostics)."""
import threading
import time
import unittest

import numpy as np
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from sensor_msgs.msg import CameraInfo, Image

W, H, F, B, Z = 640, 480, 500.0, 0.06, 0.25
DISP = int(round(F * B / Z))  # 120 px at full resolution


def texture():
    rng = np.random.default_rng(3)
    img = np.full((H, W + DISP), 128.0)
    for _ in range(3000):
        w, h = rng.integers(3, 20, 2)
        x, y = rng.integers(0, W + DISP - w), rng.integers(0, H - h)
        img[y:y + h, x:x + w] = rng.integers(0, 256)
    return img.astype(np.uint8)


def image(stamp, pixels, encoding="mono8", frame="dd_left_optical_frame"):
    m = Image()
    m.header.stamp, m.header.frame_id = stamp, frame
    m.height, m.width = pixels.shape[:2]
    m.encoding = encoding
    m.step = m.width * pixels.dtype.itemsize
    m.data = pixels.tobytes()
    return m


def info(stamp, right=False, zero_k=False, w=W, h=H):
    m = CameraInfo()
    m.header.stamp = stamp
    m.header.frame_id = "dd_right_optical_frame" if right else "dd_left_optical_frame"
    m.width, m.height = w, h
    m.distortion_model = "plumb_bob"
    m.D = [0.0] * 5
    m.K = [0.0] * 9 if zero_k else [F, 0, w / 2.0, 0, F, h / 2.0, 0, 0, 1]
    m.R = [1, 0, 0, 0, 1, 0, 0, 0, 1]
    m.P = [0.0] * 12 if zero_k else [F, 0, w / 2.0, -F * B if right else 0.0, 0, F, h / 2.0, 0, 0, 0, 1, 0]
    return m


class DenseDepthNodeletTest(unittest.TestCase):
    def setUp(self):
        rospy.init_node("dense_depth_nodelet_test", anonymous=True)
        self.pubs = {n: rospy.Publisher("/dd/" + n, Image if "image" in n else CameraInfo, queue_size=5)
                     for n in ("left/image_raw", "right/image_raw", "left/camera_info", "right/camera_info")}
        self.lock = threading.Lock()
        self.depth, self.confidence, self.infos, self.diag = [], [], [], {}
        rospy.Subscriber("/dense_depth/depth", Image, lambda m: self.add(self.depth, m))
        rospy.Subscriber("/dense_depth/confidence", Image, lambda m: self.add(self.confidence, m))
        rospy.Subscriber("/dense_depth/camera_info", CameraInfo, lambda m: self.add(self.infos, m))
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag)
        tex = texture()
        self.left, self.right = tex[:, :W].copy(), tex[:, DISP:DISP + W].copy()
        self.stamp = rospy.Time(1000)
        deadline = time.time() + 20
        while time.time() < deadline and any(p.get_num_connections() == 0 for p in self.pubs.values()):
            time.sleep(0.1)

    def add(self, store, m):
        with self.lock:
            store.append(m)

    def on_diag(self, msg):
        with self.lock:
            for s in msg.status:
                self.diag[s.name] = s

    def counter(self, name, key):
        with self.lock:
            s = self.diag.get(name)
            return int(next((v.value for v in s.values if v.key == key), 0)) if s else 0

    def send(self, left=None, right=None, left_info=None, right_info=None, frame="dd_left_optical_frame"):
        self.stamp += rospy.Duration(0.1)
        st = self.stamp
        self.pubs["left/camera_info"].publish(left_info or info(st))
        self.pubs["right/camera_info"].publish(right_info or info(st, right=True))
        self.pubs["left/image_raw"].publish(left or image(st, self.left, frame=frame))
        self.pubs["right/image_raw"].publish(right or image(st, self.right, frame="dd_right_optical_frame"))
        return st

    def wait(self, cond, timeout=30):
        deadline = time.time() + timeout
        while time.time() < deadline and not rospy.is_shutdown():
            if cond():
                return True
            time.sleep(0.05)
        return False

    def valid_pair(self):
        n = len(self.depth)
        st = self.send()
        self.assertTrue(self.wait(lambda: len(self.depth) > n), "no depth for a valid pair")
        return st

    def rejected(self, reason, **kw):
        before = self.counter("dense_depth: dense depth", "rejected." + reason)
        self.send(**kw)
        self.assertTrue(self.wait(lambda: self.counter("dense_depth: dense depth", "rejected." + reason) > before),
                        f"rejection {reason} not counted")

    def test_depth_and_bad_input(self):
        st = self.valid_pair()
        self.assertTrue(self.wait(lambda: self.confidence and self.infos))
        d = self.depth[-1]
        self.assertEqual((d.header.stamp, d.header.frame_id, d.encoding), (st, "dd_left_optical_frame", "32FC1"))
        self.assertEqual((d.width, d.height), (W // 2, H // 2))
        z = np.frombuffer(d.data, np.float32)
        good = z[np.isfinite(z)]
        self.assertGreater(good.size, 0.5 * z.size)
        self.assertAlmostEqual(float(np.median(good)), Z, delta=0.001)
        c = self.confidence[-1]
        self.assertEqual((c.encoding, c.header.stamp, c.width), ("mono8", st, W // 2))
        self.assertAlmostEqual(self.infos[-1].K[0], F / 2)

        t = self.stamp + rospy.Duration(0.1)
        self.rejected("unsupported_encoding", left=image(t, self.left, encoding="yuv422"))
        t = self.stamp + rospy.Duration(0.1)
        self.rejected("size_mismatch", right=image(t, self.right[:, :W - 8].copy(), frame="dd_right_optical_frame"))
        t = self.stamp + rospy.Duration(0.1)
        self.rejected("invalid_calibration", right_info=info(t, right=True, zero_k=True))
        t = self.stamp + rospy.Duration(0.1)
        no_frame = info(t)
        no_frame.header.frame_id = ""
        self.rejected("missing_frame_id", left=image(t, self.left, frame=""), left_info=no_frame)
        self.valid_pair()  # alive and working after all of them

    def test_invalid_parameters_refused(self):
        def refused():
            with self.lock:
                return any(n.startswith("dense_depth_invalid") and s.level == DiagnosticStatus.ERROR
                           for n, s in self.diag.items())
        self.assertTrue(self.wait(refused), "the instance with invalid parameters did not report ERROR")


if __name__ == "__main__":
    rostest.rosrun("hapi_surface", "dense_depth_nodelet", DenseDepthNodeletTest)
