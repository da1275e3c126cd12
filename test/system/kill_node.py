#!/usr/bin/python3
"""Kills a node's process (SIGKILL: a crash, no clean shutdown) some bag
seconds after the first message on a topic; for the tests that check that a
dead component fails the run (backend_dies.test).
Parameters (~): node (/hapi_manager), after_topic (/eskf/odom), after (2.0, s
of ROS time, the bag's clock under use_sim_time).
"""
import os
import signal
from xmlrpc.client import ServerProxy

import rosgraph
import rosnode
import rospy
from rospy import AnyMsg


def main():
    rospy.init_node("hapi_kill_node")
    node = rospy.get_param("~node", "/hapi_manager")
    after = float(rospy.get_param("~after", 2.0))
    rospy.wait_for_message(rospy.get_param("~after_topic", "/eskf/odom"), AnyMsg)
    start = rospy.get_time()
    while not rospy.is_shutdown() and rospy.get_time() - start < after:
        rospy.sleep(0.05)
    api = rosnode.get_api_uri(rosgraph.Master(rospy.get_name()), node, skip_cache=True)
    code, msg, pid = ServerProxy(api).getPid(rospy.get_name())
    if code != 1:
        raise RuntimeError("getPid of %s: %s" % (node, msg))
    rospy.logwarn("killing %s (pid %d) %.1f s after the first message", node, pid, after)
    os.kill(pid, signal.SIGKILL)
    rospy.spin()


if __name__ == "__main__":
    main()
