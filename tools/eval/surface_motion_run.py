"""The surface motion of a live run (evaluate_run.py's part): collects the
system's hapi_msgs/SurfaceMotion output and its truth while a bag plays,
and scores it (surface_motion_metrics).

The truth is the bag's /ground_truth/surface_motion when it has one (the
simulator's exact truth, subject motion included); otherwise the scene is
taken as static (a recording of a room) and the truth follows from the
camera's true pose and twist (/ground_truth/pose; /ground_truth/odometry,
or else central differences of the poses) and the imaging camera's
intrinsics: on the known scene's surface when the recording states its
geometry (surface_motion_metrics.truth_from_camera_motion), else at the
output's own skin point and normal (static_point_motion; a depth error of
the output then scales only the rotation's part of the truth, w x X, by
the same fraction). Stamps are moved onto the truth's clock as the poses
are (t_truth = t_output + offset).
"""
import threading

import numpy as np
import rospy
from sensor_msgs.msg import CameraInfo

import surface_motion_metrics as smm
import trajectory_metrics as tm


class SurfaceMotionCollector:
    def __init__(self):
        from hapi_msgs.msg import SurfaceMotion
        self.lock = threading.Lock()
        self.out = []     # (stamp, status, s [mm/s], covariance 3x3, normal, (u, v, rate), point [m])
        self.truth = []   # (stamp, s [mm/s], normal)
        self.K = None
        rospy.Subscriber(rospy.get_param("~surface_motion_topic", "/surface_motion/surface_motion"), SurfaceMotion,
                         self.on_output, queue_size=400)
        rospy.Subscriber(rospy.get_param("~gt_surface_motion_topic", "/ground_truth/surface_motion"), SurfaceMotion,
                         self.on_truth, queue_size=400)
        rospy.Subscriber(rospy.get_param("~imaging_info_topic", "/stereo/left/camera_info"), CameraInfo,
                         self.on_info, queue_size=2)

    @staticmethod
    def _vector(v):
        return np.array([v.x, v.y, v.z])

    def on_output(self, m):
        with self.lock:
            self.out.append((m.header.stamp.to_sec(), m.status, self._vector(m.surface_velocity),
                             np.array(m.surface_velocity_covariance).reshape(3, 3), self._vector(m.normal),
                             (m.u, m.v, m.frame_rate), self._vector(m.point)))

    def on_truth(self, m):
        if m.status == 0:
            with self.lock:
                self.truth.append((m.header.stamp.to_sec(), self._vector(m.surface_velocity), self._vector(m.normal)))

    def on_info(self, m):
        with self.lock:
            self.K = np.array(m.K).reshape(3, 3)

    def _truth_from_motion(self, t, out, gt, gt_twist, surfaces):
        """The truth at the output instants t from the camera's true motion
        (static scene): on the known surfaces, or else at each output's own
        point and normal. (s, n), NaN where unknown; (None, None) without
        the truth's poses or the camera's intrinsics."""
        with self.lock:
            K = self.K
        if K is None or len(gt["t"]) < 3:
            return None, None
        if gt_twist is None or not len(gt_twist["t"]):
            gt_twist = {"t": gt["t"], "twist": smm.twist_from_poses(gt["t"], gt["p"], tm.rotations_from_quats(gt["q"]))}
        u, v, rate = out[0][5]
        rate = rate if rate > 0 else 1.0
        ray = np.linalg.solve(K, [u, v, 1.0])
        idx, p, R = tm.interpolate_poses(gt["t"], gt["p"], tm.rotations_from_quats(gt["q"]), t, max_gap=0.2)
        s, n = np.full((len(t), 3), np.nan), np.full((len(t), 3), np.nan)
        for k, i in enumerate(idx):
            tw = np.array([np.interp(t[i], gt_twist["t"], gt_twist["twist"][:, j]) for j in range(6)])
            if surfaces is not None:
                hit = smm.truth_from_camera_motion(R[k], p[k], tw[:3], tw[3:], ray, surfaces, K[0, 0], K[1, 1], rate)
                if hit is not None:
                    s[i], n[i] = hit[2], hit[1]
            elif out[i][1] == 0:
                n[i] = out[i][4]
                s[i] = smm.static_point_motion(out[i][6], n[i], tw[:3], tw[3:], K[0, 0], K[1, 1], rate)[0]
        return s, n

    def results(self, offset, gt, gt_twist, surfaces):
        """The report's `surface_motion` entry and the plot's series; (None, None) without outputs."""
        with self.lock:
            out, truth = list(self.out), list(self.truth)
        if not out:
            return None, None
        t = np.array([o[0] for o in out]) + offset
        status = np.array([o[1] for o in out])
        rep = {"outputs": len(out), "ok_fraction": float(np.mean(status == 0)),
               "statuses": {int(k): int(np.sum(status == k)) for k in np.unique(status)}}
        if len(t) > 1 and t[-1] > t[0]:
            rep["rate_hz"] = float((len(t) - 1) / (t[-1] - t[0]))
        ok = status == 0
        if not np.any(ok):
            return rep, None
        ok &= t >= t[ok][0] + smm.SETTLE_S
        est_s = np.array([o[2] for o in out])
        cov = np.array([o[3] for o in out])
        if truth:
            tt = np.array([x[0] for x in truth])
            true_s = np.column_stack([np.interp(t, tt, np.array([x[1] for x in truth])[:, j]) for j in range(3)])
            n = np.column_stack([np.interp(t, tt, np.array([x[2] for x in truth])[:, j]) for j in range(3)])
            ok &= (t >= tt[0]) & (t <= tt[-1])
            rep["truth"] = "/ground_truth/surface_motion"
        else:
            true_s, n = self._truth_from_motion(t, out, gt, gt_twist, surfaces)
            if true_s is None:
                return rep, None
            ok &= np.all(np.isfinite(true_s), axis=1)
            rep["truth"] = ("the camera's true motion and the known scene (static)" if surfaces is not None else
                            "the camera's true motion at the output's own point (static scene of unknown geometry)")
        if np.sum(ok) < 2:
            return rep, None
        rep.update(smm.velocity_errors(est_s[ok], true_s[ok]))
        rep["depth_median_m"] = float(np.median([np.linalg.norm(o[6]) for o, k in zip(out, ok) if k]))
        rep["zero_output_rms_mm_s"] = float(np.sqrt(np.mean(np.sum(true_s[ok] ** 2, axis=1))))
        nees = smm.velocity_nees(est_s[ok], true_s[ok], cov[ok], n[ok])
        rep["nees"] = {"mean": float(np.mean(nees)), "samples": int(len(nees))}
        return rep, {"t": t[ok] - t[ok][0], "estimate": est_s[ok], "truth": true_s[ok]}
