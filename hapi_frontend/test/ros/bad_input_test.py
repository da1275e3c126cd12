#!/usr/bin/env python3
"""rostest node: feeds the front end valid and malformed stereo frames
(frontend_bad_input.test) and checks that it survives, keeps processing valid
frames, and counts each rejection reason in /diagnostics; also that the
instance started with invalid parameters reports ERROR and publishes nothing.

Valid frames are a synthetic rectified pair: a random blocky texture (many
FAST corners) and the same texture shifted by a constant disparity. Each
frame is sent once the previous one's outcome is seen (its landmarks, or its
rejection counted in /diagnostics), not after a fixed sleep, so a slow machine
cannot merge or drop frames.
"""
import sys
import threading
import time
import unittest

import numpy as np
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from hapi_msgs.msg import StereoLandmarks
from sensor_msgs.msg import CameraInfo, Image

W, H, F, CX, CY, B, DISP = 640, 480, 500.0, 320.0, 240.0, 0.1, 16


def texture():
    # "Dead leaves": overlapping random rectangles of random grey levels. Their
    # corners are distinct (different neighbourhoods), unlike a periodic
    # pattern whose repeated descriptors would fail the ratio test.
    rng = np.random.default_rng(7)
    img = np.full((H, W + DISP), 128.0)
    for _ in range(1500):
        w, h = rng.integers(6, 60, 2)
        x, y = rng.integers(0, W + DISP - w), rng.integers(0, H - h)
        img[y:y + h, x:x + w] = rng.integers(0, 256)
    pad = np.pad(img, 1, mode="edge")  # 3x3 blur: sub-pixel-like edges
    img = sum(pad[dy:dy + H, dx:dx + W + DISP] for dy in range(3) for dx in range(3)) / 9.0
    return img.astype(np.uint8)


def image(stamp, pixels, encoding="mono8", frame="bad_left_optical_frame"):
    m = Image()
    m.header.stamp, m.header.frame_id = stamp, frame
    m.height, m.width = pixels.shape[:2]
    m.encoding = encoding
    m.step = m.width * (pixels.shape[2] if pixels.ndim == 3 else 1) * pixels.dtype.itemsize
    m.data = pixels.tobytes()
    return m


def info(stamp, w=W, h=H, right=False, zero_k=False):
    m = CameraInfo()
    m.header.stamp = stamp
    m.header.frame_id = "bad_right_optical_frame" if right else "bad_left_optical_frame"
    m.width, m.height = w, h
    m.distortion_model = "plumb_bob"
    m.D = [0.0] * 5
    m.K = [0.0] * 9 if zero_k else [F, 0, w / 2.0, 0, F, h / 2.0, 0, 0, 1]
    m.R = [1, 0, 0, 0, 1, 0, 0, 0, 1]
    m.P = [F, 0, w / 2.0, -F * B if right else 0.0, 0, F, h / 2.0, 0, 0, 0, 1, 0]
    return m


class BadInputTest(unittest.TestCase):
    def setUp(self):
        rospy.init_node("bad_input_test", anonymous=True)
        self.pubs = self.publishers(rospy.get_param("~prefix"))
        self.approx_pubs = self.publishers("/approx")
        self.lock = threading.Lock()
        self.landmarks = []
        self.approx_landmarks = []
        self.diag = {}
        rospy.Subscriber(rospy.get_param("~landmarks_topic"), StereoLandmarks, self.on_landmarks, queue_size=50)
        rospy.Subscriber("/stereo_frontend_approx/landmarks", StereoLandmarks, self.on_approx_landmarks,
                         queue_size=50)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag, queue_size=50)
        tex = texture()
        self.left = tex[:, :W].copy()      # texture column X is at left x = X
        self.right = tex[:, DISP:].copy()  # and at right x = X - DISP: disparity +DISP

    @staticmethod
    def publishers(prefix):
        return [rospy.Publisher(prefix + t, c, queue_size=10) for t, c in
                (("/left/image_raw", Image), ("/left/camera_info", CameraInfo),
                 ("/right/image_raw", Image), ("/right/camera_info", CameraInfo))]

    @staticmethod
    def wait_connected(pubs):
        deadline = rospy.Time.now() + rospy.Duration(30)
        while any(p.get_num_connections() == 0 for p in pubs):
            if rospy.Time.now() > deadline:
                return False
            rospy.sleep(0.1)
        return True

    def on_landmarks(self, m):
        with self.lock:
            self.landmarks.append(m)

    def on_approx_landmarks(self, m):
        with self.lock:
            self.approx_landmarks.append(m)

    def on_diag(self, a):
        with self.lock:
            for s in a.status:
                self.diag[s.name] = s

    def send(self, limg, linfo, rimg, rinfo, pubs=None):
        for pub, m in zip(pubs or self.pubs, (limg, linfo, rimg, rinfo)):
            pub.publish(m)

    @staticmethod
    def wait(predicate, timeout=10.0):
        deadline = time.time() + timeout
        while not predicate():
            if time.time() > deadline or rospy.is_shutdown():
                return False
            rospy.sleep(0.02)
        return True

    def published(self, stamp, msgs):
        with self.lock:
            return any(m.header.stamp == stamp for m in msgs)

    def valid(self, t):
        """A valid pair; returns once its landmarks arrived."""
        self.send(image(t, self.left), info(t), image(t, self.right, frame="bad_right_optical_frame"),
                  info(t, right=True))
        self.assertTrue(self.wait(lambda: self.published(t, self.landmarks)),
                        "no landmarks for the valid frame at %s" % t)

    def counter(self, key, name="stereo_frontend: stereo front end"):
        s = self.status(name)
        v = self.value(s, key) if s is not None else None
        return int(v) if v is not None else 0

    def rejected(self, key, limg, linfo, rimg, rinfo):
        """A bad pair; returns once /diagnostics counted it under key."""
        before = self.counter(key)
        self.send(limg, linfo, rimg, rinfo)
        self.assertTrue(self.wait(lambda: self.counter(key) > before), "%s not counted" % key)

    def status(self, name):
        with self.lock:
            return self.diag.get(name)

    @staticmethod
    def value(status, key):
        for kv in status.values:
            if kv.key == key:
                return kv.value
        return None

    def test_bad_input(self):
        self.assertTrue(self.wait_connected(self.pubs), "front end never subscribed")
        self.assertTrue(self.wait_connected(self.approx_pubs), "approximate-sync front end never subscribed")
        rospy.sleep(1.0)

        t = rospy.Time.now()
        step = rospy.Duration(0.1)
        for _ in range(3):
            t += step
            self.valid(t)
        with self.lock:
            n_before = len(self.landmarks)
        self.assertGreater(n_before, 0, "no landmarks for the valid synthetic frames")

        r_frame = "bad_right_optical_frame"
        # 1. unsupported encoding (bgra8)
        t += step
        bgra = np.dstack([self.left] * 4)
        self.rejected("rejected.unsupported_encoding", image(t, bgra, "bgra8"), info(t),
                      image(t, self.right, frame=r_frame), info(t, right=True))
        # 2. left and right sizes differ
        t += step
        small = self.right[::2, ::2].copy()
        self.rejected("rejected.size_mismatch", image(t, self.left), info(t), image(t, small, frame=r_frame),
                      info(t, W // 2, H // 2, right=True))
        # 3. zero K on the left camera
        t += step
        self.rejected("rejected.invalid_calibration", image(t, self.left), info(t, zero_k=True),
                      image(t, self.right, frame=r_frame), info(t, right=True))
        # 4. truncated image buffer
        t += step
        trunc = image(t, self.left)
        trunc.data = trunc.data[: len(trunc.data) // 2]
        self.rejected("rejected.malformed_image", trunc, info(t), image(t, self.right, frame=r_frame),
                      info(t, right=True))
        # 5. stamp going back (by less than time_jump_reset: not a time reset)
        back = t - rospy.Duration(0.05)
        self.rejected("rejected.stamp_not_increasing", image(back, self.left), info(back),
                      image(back, self.right, frame=r_frame), info(back, right=True))
        # 6. valid frames again: the nodelet must still be working
        for _ in range(3):
            t += step
            self.valid(t)

        expected = {"rejected.unsupported_encoding": 1, "rejected.size_mismatch": 1,
                    "rejected.invalid_calibration": 1, "rejected.malformed_image": 1,
                    "rejected.stamp_not_increasing": 1, "frames processed": 6}
        deadline = rospy.Time.now() + rospy.Duration(15)
        while True:
            s = self.status("stereo_frontend: stereo front end")
            ok = s is not None and all(self.value(s, k) is not None and int(self.value(s, k)) >= v
                                       for k, v in expected.items())
            if ok or rospy.Time.now() > deadline:
                break
            rospy.sleep(0.2)
        self.assertIsNotNone(s, "no diagnostics from the front end")
        for k, v in expected.items():
            self.assertIsNotNone(self.value(s, k), "missing counter %s in %s" % (k, s.values))
            self.assertEqual(int(self.value(s, k)), v, k)

        with self.lock:
            msgs = list(self.landmarks)
        rospy.loginfo("landmarks per valid frame: %s", [len(m.landmarks) for m in msgs])
        self.assertEqual(len(msgs), 6, "expected exactly the 6 valid frames to be published")
        self.assertGreater(msgs[-1].header.stamp, t - step * 3, "no output after the bad input")
        for m in msgs:
            self.assertEqual(m.header.frame_id, "bad_left_optical_frame")
            self.assertGreaterEqual(len(m.landmarks), 150)
            self.assertEqual(len(m.descriptors), len(m.landmarks) * m.descriptor_length)
            # Constant disparity DISP -> depth F*B/DISP for every landmark.
            z = np.array([l.position.z for l in m.landmarks])
            self.assertLess(abs(np.median(z) - F * B / DISP), 0.05 * F * B / DISP)

        self.assertEqual(int(self.value(s, "rejected total")), 5)

        # Approximate sync: right stamps 2 ms late are paired and processed;
        # 50 ms late (> approx_slop 5 ms) is paired but rejected, and counted.
        r_frame = "bad_right_optical_frame"
        # (The approximate policy may hold a pair until later messages arrive:
        # each pair gets a short wait for its outcome, the counts are checked
        # after the last one.)
        approx = "stereo_frontend_approx: stereo front end"
        for k, offset in enumerate((0.002, 0.002, 0.05, 0.002, 0.002, 0.002)):
            ta = t + rospy.Duration(1.0 + 0.1 * k)
            tr = ta + rospy.Duration(offset)
            before = self.counter("rejected.unsynchronised", approx)
            self.send(image(ta, self.left), info(ta), image(tr, self.right, frame=r_frame), info(tr, right=True),
                      pubs=self.approx_pubs)
            self.wait(lambda: self.published(ta, self.approx_landmarks)
                      or self.counter("rejected.unsynchronised", approx) > before, timeout=2.0)
        deadline = rospy.Time.now() + rospy.Duration(10)
        while True:
            a = self.status("stereo_frontend_approx: stereo front end")
            if (a is not None and self.value(a, "rejected.unsynchronised") is not None
                    and int(self.value(a, "frames processed")) >= 3) or rospy.Time.now() > deadline:
                break
            rospy.sleep(0.2)
        self.assertIsNotNone(a, "no diagnostics from the approximate-sync instance")
        self.assertEqual(self.value(a, "rejected.unsynchronised"), "1", a.values)
        self.assertEqual(self.value(a, "rejected total"), "1", a.values)
        self.assertGreaterEqual(int(self.value(a, "frames processed")), 3)
        self.assertGreaterEqual(len(self.approx_landmarks), 3)
        late = [m for m in self.approx_landmarks if m.header.stamp == t + rospy.Duration(1.2)]
        self.assertEqual(late, [], "the unsynchronised pair was published")

        # The instance with invalid parameters refuses to run, loudly.
        bad = self.status("stereo_frontend_invalid: stereo front end")
        self.assertIsNotNone(bad, "no diagnostics from the invalid instance")
        self.assertEqual(bad.level, DiagnosticStatus.ERROR)
        self.assertIn("invalid parameters", bad.message)
        self.assertIn("detector", bad.message)
        nt = self.status("stereo_frontend_no_transport: stereo front end")
        self.assertIsNotNone(nt, "no diagnostics from the instance without transport plugin")
        self.assertEqual(nt.level, DiagnosticStatus.ERROR)
        self.assertIn("no_such_transport", nt.message)


if __name__ == "__main__":
    rostest.rosrun("hapi_frontend", "bad_input", BadInputTest, sys.argv)
