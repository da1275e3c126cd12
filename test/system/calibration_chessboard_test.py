#!/usr/bin/python3
"""The calibration path of docs/CALIBRATION.md end to end: a chessboard
waved in front of the simulated stereo rig (make_sim_bag --scene chessboard
--trajectory calibration) through cameracalibrator.py's own solver
(camera_calibration.calibrator.StereoCalibrator, Debian's
python3-camera-calibration), and its result against the simulator's true
intrinsics and baseline (the bag's CameraInfo).

  calibration_chessboard_test.py BAG [SCENE_BAG]

Bounds: focal lengths within 1 %, principal point within 3 px, baseline
within 2 %, the right camera's rotation within 0.5 deg. With SCENE_BAG (a
recording of the same simulated rig), the pipeline then runs on it twice,
offline as tools/eval/accuracy.py does (frontend_replay, eskf_replay with
the inertial model): once with the recording's true CameraInfo, once with
the calibration's in its place. Its ATE with the calibration must be
within MAX_ATE_RATIO of the ATE with the truth, plus MAX_ATE_EXTRA_PCT
(absolute). Exit 0 pass, 1 fail, 77 skip (camera_calibration not
installed).
"""
import math
import os
import sys
import tempfile

import numpy as np

try:
    from camera_calibration.calibrator import ChessboardInfo, StereoCalibrator
except ImportError as e:
    print("[ HAPI SKIPPED ] camera_calibration not importable (%s): apt-get install python3-camera-calibration" % e)
    sys.exit(77)
import rosbag

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "eval"))
import accuracy  # noqa: E402

# hapi_sim/include/hapi_sim/scene.hpp: kChessboardCols, kChessboardRows, kChessboardSquare.
COLS, ROWS, SQUARE = 8, 6, 0.03
MAX_F_REL, MAX_C_PX, MAX_BASELINE_REL, MAX_ROT_DEG = 0.01, 3.0, 0.02, 0.5
MAX_ATE_RATIO, MAX_ATE_EXTRA_PCT = 1.5, 0.05
CAMERA_INFO = {"/stereo/left/camera_info": 0, "/stereo/right/camera_info": 1}


def mono(msg):
    assert msg.encoding == "mono8", msg.encoding
    return np.frombuffer(msg.data, dtype=np.uint8).reshape(msg.height, msg.width).copy()


def read(bag_path):
    left, right, info = {}, {}, {}
    with rosbag.Bag(bag_path) as bag:
        for topic, msg, _ in bag.read_messages(["/stereo/left/image_raw", "/stereo/right/image_raw",
                                                "/stereo/left/camera_info", "/stereo/right/camera_info"]):
            stamp = msg.header.stamp.to_nsec()
            if topic.endswith("left/image_raw"):
                left[stamp] = mono(msg)
            elif topic.endswith("right/image_raw"):
                right[stamp] = mono(msg)
            else:
                info[topic.split("/")[2]] = msg
    stamps = sorted(set(left) & set(right))
    return [left[s] for s in stamps], [right[s] for s in stamps], info


def with_calibration(scene_bag, calibrated, out_bag):
    """A copy of scene_bag whose stereo CameraInfo is the calibration's
    (left, right: cameracalibrator.py's messages), headers kept."""
    with rosbag.Bag(scene_bag) as src, rosbag.Bag(out_bag, "w") as dst:
        for topic, msg, t in src.read_messages():
            if topic in CAMERA_INFO:
                c = calibrated[CAMERA_INFO[topic]]
                msg.distortion_model, msg.D, msg.K, msg.R, msg.P = c.distortion_model, c.D, c.K, c.R, c.P
            dst.write(topic, msg, t)


def pipeline_ate(bag, name, work):
    """ATE % of the offline pipeline (inertial) on one bag, against its truth."""
    log = os.path.join(work, "pipeline.log")
    txt = accuracy.landmark_stream(bag, name, [], work, log)
    (row,) = accuracy.score_stream(name, bag, txt, ["inertial"], 1, work, log, [])
    if row["diverged"] or row["metrics"] is None:
        return float("inf")
    return 100.0 * row["metrics"]["ate_fraction_of_distance"]


def check_pipeline(calibrator, scene_bag, check):
    with tempfile.TemporaryDirectory() as work:
        calibrated_bag = os.path.join(work, "calibrated.bag")
        with_calibration(scene_bag, calibrator.as_message(), calibrated_bag)
        ate_true = pipeline_ate(scene_bag, "true_calibration", work)
        ate_cal = pipeline_ate(calibrated_bag, "calibrated", work)
    check("ATE % (calibrated)", ate_cal, ate_true, (MAX_ATE_RATIO - 1.0) * ate_true + MAX_ATE_EXTRA_PCT)


def main():
    limages, rimages, info = read(sys.argv[1])
    calibrator = StereoCalibrator([ChessboardInfo(n_cols=COLS, n_rows=ROWS, dim=SQUARE)])
    calibrator.cal(limages, rimages)
    failures = []

    def check(name, value, truth, bound):
        ok = abs(value - truth) <= bound
        print("%-22s %10.4f  truth %10.4f  bound %.4f  %s" % (name, value, truth, bound, "ok" if ok else "FAIL"))
        if not ok:
            failures.append(name)

    for side, mono_cal in (("left", calibrator.l), ("right", calibrator.r)):
        K_true = np.array(info[side].K).reshape(3, 3)
        K = np.array(mono_cal.intrinsics).reshape(3, 3)
        check(side + " fx [px]", K[0, 0], K_true[0, 0], MAX_F_REL * K_true[0, 0])
        check(side + " fy [px]", K[1, 1], K_true[1, 1], MAX_F_REL * K_true[1, 1])
        check(side + " cx [px]", K[0, 2], K_true[0, 2], MAX_C_PX)
        check(side + " cy [px]", K[1, 2], K_true[1, 2], MAX_C_PX)
    # The truth's baseline: P_right[0,3] = -fx' * B.
    P_right = np.array(info["right"].P).reshape(3, 4)
    baseline_true = -P_right[0, 3] / P_right[0, 0]
    baseline = float(np.linalg.norm(calibrator.T))
    check("baseline [m]", baseline, baseline_true, MAX_BASELINE_REL * baseline_true)
    # The truth's rotation between the cameras: R_left^T R_right of the rectification.
    R_true = np.array(info["left"].R).reshape(3, 3).T @ np.array(info["right"].R).reshape(3, 3)
    R_err = np.asarray(calibrator.R) @ R_true  # R maps left to right points: R = R_lr^T
    angle = math.degrees(math.acos(max(-1.0, min(1.0, (np.trace(R_err) - 1) / 2))))
    check("rotation error [deg]", angle, 0.0, MAX_ROT_DEG)
    print("%d stereo pairs" % len(limages))
    if len(sys.argv) > 2:
        check_pipeline(calibrator, sys.argv[2], check)
    if failures:
        print("FAILED: " + ", ".join(failures))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
