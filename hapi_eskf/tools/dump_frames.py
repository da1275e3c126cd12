#!/usr/bin/env python3
"""Dump what the back end reads from a bag into a plain text file read by
eskf_replay (ROS-free), so the filter can be studied and evaluated frame by
frame without real-time drops: the front end's StereoLandmarks, the IMU, the
camera-IMU extrinsic from /tf_static, the ground truth and the scene geometry.

    dump_frames.py IN.bag OUT.txt [--landmarks /stereo_frontend/landmarks] [--imu /imu/data]

IN.bag holds landmarks: a recorded live run, or hapi_frontend's frontend_replay
output. Lines (stamps in seconds, as in the bag):
  globe cx cy cz r                       the globe's centre and radius (/globe/info)
  scene JSON                             the scene description (/ground_truth/scene, one line)
  gt t px py pz qx qy qz qw              true left camera pose in the world
  gtvel t vx vy vz wx wy wz              true camera twist, camera frame (/ground_truth/odometry)
  extrinsic r00 .. r22 px py pz          the camera in the IMU frame, X_imu = R X_cam + p
  imu t wx wy wz ax ay az                an IMU sample, IMU frame, IMU clock
  frame t n descriptor_length            then n lines:
  m id response r g b zx zy zz c00 .. c22 hexdescriptor
"""
import argparse
import binascii
import json
import os
import sys

import numpy as np
import rosbag
import yaml

# The one quaternion convention of the evaluation tools (tools/eval/evaluation.py).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "eval"))
from evaluation import quat_to_rot  # noqa: E402


def static_transforms(bag):
    """{(parent, child): (R, p)} with X_parent = R X_child + p."""
    out = {}
    for _, msg, _ in bag.read_messages(topics=["/tf_static"]):
        for t in msg.transforms:
            r, p = t.transform.rotation, t.transform.translation
            out[(t.header.frame_id, t.child_frame_id)] = (quat_to_rot((r.x, r.y, r.z, r.w)),
                                                          np.array([p.x, p.y, p.z]))
    return out


def camera_in_imu(tfs, camera, imu):
    """(R, p) with X_imu = R X_cam + p from a direct static transform, either direction."""
    if camera == imu:
        return np.eye(3), np.zeros(3)
    if (imu, camera) in tfs:
        return tfs[(imu, camera)]
    if (camera, imu) in tfs:
        R, p = tfs[(camera, imu)]
        return R.T, -R.T @ p
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bag")
    ap.add_argument("out")
    ap.add_argument("--landmarks", default="/stereo_frontend/landmarks")
    ap.add_argument("--imu", default="/imu/data")
    ap.add_argument("--gt", default="/ground_truth/pose")
    ap.add_argument("--gt-odometry", default="/ground_truth/odometry")
    a = ap.parse_args()
    with rosbag.Bag(a.bag) as b, open(a.out, "w") as f:
        tfs = static_transforms(b)
        globe_done = scene_done = extrinsic_done = False
        camera_frame = imu_frame = None
        pending_imu = []  # written once the extrinsic is known (it needs both frame names)
        topics = [a.landmarks, a.gt, a.gt_odometry, a.imu, "/globe/info", "/ground_truth/scene"]
        for topic, msg, _ in b.read_messages(topics=topics):
            if topic == "/globe/info" and not globe_done:
                g = yaml.safe_load(msg.data)
                c = g.get("centre", [0, 0, 0])
                f.write("globe %r %r %r %r\n" % (c[0], c[1], c[2], g["radius"]))
                globe_done = True
            elif topic == "/ground_truth/scene" and not scene_done:
                f.write("scene %s\n" % json.dumps(yaml.safe_load(msg.data)))
                scene_done = True
            elif topic == a.gt:
                p, q = msg.pose.position, msg.pose.orientation
                f.write("gt %.9f %r %r %r %r %r %r %r\n" % (msg.header.stamp.to_sec(), p.x, p.y, p.z, q.x, q.y, q.z, q.w))
            elif topic == a.gt_odometry:
                v, w = msg.twist.twist.linear, msg.twist.twist.angular
                f.write("gtvel %.9f %r %r %r %r %r %r\n" % (msg.header.stamp.to_sec(), v.x, v.y, v.z, w.x, w.y, w.z))
            elif topic == a.imu:
                imu_frame = imu_frame or msg.header.frame_id
                w, acc = msg.angular_velocity, msg.linear_acceleration
                line = "imu %.9f %r %r %r %r %r %r\n" % (msg.header.stamp.to_sec(), w.x, w.y, w.z, acc.x, acc.y, acc.z)
                if extrinsic_done:
                    f.write(line)
                else:
                    pending_imu.append(line)
            elif topic == a.landmarks:
                camera_frame = camera_frame or msg.header.frame_id
                L = msg.descriptor_length
                f.write("frame %.9f %d %d\n" % (msg.header.stamp.to_sec(), len(msg.landmarks), L))
                d = bytes(msg.descriptors)
                for i, l in enumerate(msg.landmarks):
                    f.write("m %d %r %d %d %d %r %r %r %s %s\n" % (
                        l.id, l.response, l.r, l.g, l.b, l.position.x, l.position.y, l.position.z,
                        " ".join(repr(x) for x in l.position_covariance),
                        binascii.hexlify(d[i * L:(i + 1) * L]).decode()))
            if not extrinsic_done and camera_frame and imu_frame:
                e = camera_in_imu(tfs, camera_frame, imu_frame)
                if e is None:
                    raise SystemExit("no /tf_static transform between %s and %s: the IMU cannot be used"
                                     % (camera_frame, imu_frame))
                R, p = e
                f.write("extrinsic %s %s\n" % (" ".join(repr(float(x)) for x in R.reshape(-1)),
                                               " ".join(repr(float(x)) for x in p)))
                extrinsic_done = True
                f.writelines(pending_imu)
                pending_imu = []


if __name__ == "__main__":
    main()
