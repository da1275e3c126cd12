#!/usr/bin/env python3
"""Writes stereo frames of a bag as 8-bit PGM files for the GPU machine, which
has neither ROS nor OpenCV: hapi_frontend_gpu_test reads them through
HAPI_TEST_FRAMES and hapi_frontend_gpu_bench through --dir (consecutive files
= left, right). Put them in a git-ignored folder and carry it with the call.

  bag_frames_to_pgm.py BAG OUT_DIR [--step 5] [--pairs 50]
"""
import argparse
import os
import sys

import numpy as np
import rosbag


def to_grey(msg):
    a = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.step)
    if msg.encoding == 'mono8':
        return a[:, :msg.width]
    if msg.encoding in ('bgr8', 'rgb8'):
        c = a[:, :msg.width * 3].reshape(msg.height, msg.width, 3).astype(np.int32)
        if msg.encoding == 'bgr8':
            c = c[:, :, ::-1]
        # ITU-R BT.601 weights in 8-bit fixed point.
        return ((77 * c[:, :, 0] + 150 * c[:, :, 1] + 29 * c[:, :, 2] + 128) >> 8).astype(np.uint8)
    raise ValueError('unsupported encoding ' + msg.encoding)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('bag')
    ap.add_argument('out_dir')
    ap.add_argument('--left', default='/stereo/left/image_raw')
    ap.add_argument('--right', default='/stereo/right/image_raw')
    ap.add_argument('--step', type=int, default=5, help='keep every STEP-th pair')
    ap.add_argument('--pairs', type=int, default=50, help='number of pairs written')
    a = ap.parse_args()
    if a.step < 1 or a.pairs < 1:
        sys.exit('--step and --pairs must be >= 1')
    os.makedirs(a.out_dir, exist_ok=True)
    count = {a.left: 0, a.right: 0}
    written = 0
    with rosbag.Bag(a.bag) as bag:
        for topic, msg, _ in bag.read_messages(topics=[a.left, a.right]):
            i = count[topic]
            count[topic] += 1
            if i % a.step or i // a.step >= a.pairs:
                continue
            side = 'L' if topic == a.left else 'R'
            g = np.ascontiguousarray(to_grey(msg))
            with open(os.path.join(a.out_dir, 'frame_%05d_%s.pgm' % (i, side)), 'wb') as f:
                f.write(b'P5\n%d %d\n255\n' % (msg.width, msg.height))
                f.write(g.tobytes())
            written += 1
    print('%d images written to %s' % (written, a.out_dir))
    return 0 if written else 1


if __name__ == '__main__':
    sys.exit(main())
