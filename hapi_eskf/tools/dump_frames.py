#!/usr/bin/env python3
"""Dump the front end's StereoLandmarks, the ground truth and the globe geometry
from a rosbag into a plain text file read by eskf_replay (ROS-free), so the
filter can be studied frame by frame without real-time drops.

    dump_frames.py IN.bag OUT.txt [--landmarks /stereo_frontend/landmarks]

Lines: `globe cx cy cz r`, `gt t px py pz qx qy qz qw`,
`frame t n descriptor_length`, then n lines
`m id response r g b zx zy zz c00 .. c22 hexdescriptor`.
"""
import argparse
import binascii

import rosbag
import yaml


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bag")
    ap.add_argument("out")
    ap.add_argument("--landmarks", default="/stereo_frontend/landmarks")
    ap.add_argument("--gt", default="/ground_truth/pose")
    a = ap.parse_args()
    with rosbag.Bag(a.bag) as b, open(a.out, "w") as f:
        globe_done = False
        for topic, msg, _ in b.read_messages(topics=[a.landmarks, a.gt, "/globe/info"]):
            if topic == "/globe/info" and not globe_done:
                g = yaml.safe_load(msg.data)
                c = g.get("centre", [0, 0, 0])
                f.write("globe %r %r %r %r\n" % (c[0], c[1], c[2], g["radius"]))
                globe_done = True
            elif topic == a.gt:
                p, q = msg.pose.position, msg.pose.orientation
                f.write("gt %.9f %r %r %r %r %r %r %r\n" % (msg.header.stamp.to_sec(), p.x, p.y, p.z, q.x, q.y, q.z, q.w))
            elif topic == a.landmarks:
                L = msg.descriptor_length
                f.write("frame %.9f %d %d\n" % (msg.header.stamp.to_sec(), len(msg.landmarks), L))
                d = bytes(msg.descriptors)
                for i, l in enumerate(msg.landmarks):
                    f.write("m %d %r %d %d %d %r %r %r %s %s\n" % (
                        l.id, l.response, l.r, l.g, l.b, l.position.x, l.position.y, l.position.z,
                        " ".join(repr(x) for x in l.position_covariance),
                        binascii.hexlify(d[i * L:(i + 1) * L]).decode()))


if __name__ == "__main__":
    main()
