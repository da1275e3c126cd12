#!/usr/bin/python3
"""Puts the simulator's ground truth next to the estimate in rviz.

The globe bag carries the true camera pose in its own frame tree,
world -> ground_truth/stereo_left_optical_frame (/tf, /ground_truth/pose),
so it never fights with the filter's map -> stereo_left_optical_frame.
The filter's map frame is its first camera pose, the bag's world is the
globe's frame: the two differ by an unknown rigid transform. This node
anchors them at the first odometry message that has a ground-truth pose with
the same stamp,

    T_map_world = T_map_cam(estimate, t0) * T_world_cam(truth, t0)^-1,

publishes it once as a static transform map -> world, and republishes the
ground truth as a nav_msgs/Path in `world` (~path, default
/ground_truth/path) for rviz. Visual comparison only: the metrics use a least
squares alignment of the whole trajectory (tools/eval/evaluation.py).
"""
import os
import sys
import threading

import numpy as np
import rospy
import tf2_ros
from geometry_msgs.msg import PoseStamped, TransformStamped
from nav_msgs.msg import Odometry, Path

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluation import quat_to_rot, rot_to_quat  # noqa: E402  (installed next to this node)


def pose_to_matrix(pose):
    t = np.eye(4)
    o, p = pose.orientation, pose.position
    t[:3, :3] = quat_to_rot((o.x, o.y, o.z, o.w))
    t[:3, 3] = [p.x, p.y, p.z]
    return t


class GroundTruthTf:
    def __init__(self):
        self.map_frame = rospy.get_param("~map_frame", "map")
        self.max_dt = float(rospy.get_param("~max_dt", 0.006))  # [s] stamp match tolerance
        self.max_length = int(rospy.get_param("~path_max_length", 10000))
        if self.max_dt <= 0 or self.max_length <= 0:
            raise ValueError("~max_dt and ~path_max_length must be positive")
        self.lock = threading.Lock()
        self.gt = {}       # stamp [ns] -> 4x4 T_world_cam, until anchored
        self.est = {}      # stamp [ns] -> 4x4 T_map_cam, until anchored
        self.anchored = False
        self.world_frame = None
        self.path = Path()
        self.broadcaster = tf2_ros.StaticTransformBroadcaster()
        self.path_pub = rospy.Publisher(rospy.get_param("~path", "/ground_truth/path"), Path, queue_size=1, latch=True)
        rospy.Subscriber(rospy.get_param("~gt_topic", "/ground_truth/pose"), PoseStamped, self.on_gt, queue_size=50)
        rospy.Subscriber(rospy.get_param("~odom_topic", "/eskf/odom"), Odometry, self.on_odom, queue_size=50)

    def on_gt(self, msg):
        with self.lock:
            if self.path.poses and msg.header.stamp < self.path.poses[-1].header.stamp - rospy.Duration(0.5):
                # Bag looped (time jumped backwards): the filter restarts its
                # map at the new first pose, so anchor again.
                rospy.logwarn("ground truth time jumped backwards: re-anchoring")
                self.path.poses = []
                self.anchored = False
                self.gt.clear()
                self.est.clear()
            if self.world_frame is None:
                self.world_frame = msg.header.frame_id
                self.path.header.frame_id = msg.header.frame_id
            self.path.header.stamp = msg.header.stamp
            self.path.poses.append(msg)
            del self.path.poses[:-self.max_length]
            if not self.anchored:
                self.gt[msg.header.stamp.to_nsec()] = pose_to_matrix(msg.pose)
                self.try_anchor()
            path = self.path
        self.path_pub.publish(path)

    def on_odom(self, msg):
        with self.lock:
            if self.anchored:
                return
            if msg.header.frame_id and msg.header.frame_id != self.map_frame:
                rospy.logwarn_throttle(10, "odometry in '%s', expected ~map_frame '%s'", msg.header.frame_id,
                                       self.map_frame)
            self.est[msg.header.stamp.to_nsec()] = pose_to_matrix(msg.pose.pose)
            self.try_anchor()

    def try_anchor(self):
        """Called with the lock held; publishes map -> world once."""
        tol = int(self.max_dt * 1e9)
        for ts, t_map_cam in sorted(self.est.items()):
            match = [g for g in self.gt if abs(g - ts) <= tol]
            if not match:
                continue
            t_world_cam = self.gt[min(match, key=lambda g: abs(g - ts))]
            t_map_world = t_map_cam @ np.linalg.inv(t_world_cam)
            tf = TransformStamped()
            tf.header.stamp = rospy.Time(0, ts)  # canonicalised to (secs, nsecs)
            tf.header.frame_id = self.map_frame
            tf.child_frame_id = self.world_frame
            tf.transform.translation.x, tf.transform.translation.y, tf.transform.translation.z = t_map_world[:3, 3]
            q = rot_to_quat(t_map_world[:3, :3])
            (tf.transform.rotation.x, tf.transform.rotation.y, tf.transform.rotation.z,
             tf.transform.rotation.w) = q
            self.broadcaster.sendTransform(tf)
            self.anchored = True
            self.gt.clear()
            self.est.clear()
            rospy.loginfo("ground truth anchored: %s -> %s at t=%.3f", self.map_frame, self.world_frame, ts * 1e-9)
            return
        # Bound the buffers while waiting for the first match.
        for buf in (self.gt, self.est):
            for k in sorted(buf)[:-500]:
                del buf[k]


def main():
    rospy.init_node("ground_truth_tf")
    try:
        GroundTruthTf()
    except ValueError as e:
        rospy.logfatal("ground_truth_tf: %s", e)
        raise SystemExit(2)
    rospy.spin()


if __name__ == "__main__":
    main()
