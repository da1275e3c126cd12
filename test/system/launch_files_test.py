#!/usr/bin/python3
"""Static checks of the system's launch files (no master, no nodes started).

Each file is loaded by roslaunch's own XML loader with representative
arguments, so a typo, a missing/unknown <arg>, a wrong package or executable,
or a nodelet that is not declared fails here, in seconds, instead of in the
middle of an end-to-end run. It also pins the system's wiring: topics between
front end and back end, use_sim_time + --clock in replay, one shared manager in
all_in_one, and which machine each node of distributed.launch runs on.
Needs the devel-space environment (ctest runs it through catkin's env.sh).
"""
import os
import subprocess
import unittest
from xml.dom import minidom

import roslaunch.config
import roslaunch.xmlloader
import roslib.packages
import rospkg

PKG = "hapi_slam"
LAUNCH = os.path.join(rospkg.RosPack().get_path(PKG), "launch")


def load(name, *args):
    cfg = roslaunch.config.ROSLaunchConfig()
    roslaunch.xmlloader.XmlLoader().load(os.path.join(LAUNCH, name), cfg, argv=list(args), verbose=False)
    return cfg


def declared_nodelets():
    """Nodelet class names pluginlib will find. Through rospack (C++), as
    pluginlib does: `rosrun nodelet declared_nodelets` (Python rospkg) lists
    nothing on a machine without an initialised rosdep."""
    out = subprocess.run(["rospack", "plugins", "--attrib=plugin", "nodelet"], capture_output=True, text=True,
                         timeout=60)
    names = set()
    for line in out.stdout.splitlines():
        parts = line.split(None, 1)
        if len(parts) == 2 and os.path.isfile(parts[1].strip()):
            dom = minidom.parse(parts[1].strip())
            names.update(c.getAttribute("name") for c in dom.getElementsByTagName("class"))
    return names


def nodes(cfg):
    return {n.namespace.rstrip("/") + "/" + n.name: n for n in cfg.nodes}


def remaps(node):
    return dict(node.remap_args)


class LaunchFilesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.nodelets = declared_nodelets()

    def check_runnable(self, cfg):
        """Every node's executable exists; every nodelet is declared and loaded into a manager of this launch."""
        self.assertEqual(cfg.config_errors, [], cfg.config_errors)
        ns = nodes(cfg)
        managers = {name for name, n in ns.items() if n.package == "nodelet" and n.args.split()[:1] == ["manager"]}
        for name, n in ns.items():
            paths = roslib.packages.find_node(n.package, n.type)
            self.assertTrue(paths, f"{name}: no executable {n.package}/{n.type}")
            if n.package == "nodelet" and n.args.startswith("load"):
                _, plugin, manager = n.args.split()[:3]
                self.assertIn(plugin, self.nodelets, f"{name}: nodelet {plugin} not declared (built?)")
                self.assertIn("/" + manager, managers, f"{name}: manager {manager} not started by this launch")
        return ns

    def test_server(self):
        ns = self.check_runnable(load("server.launch"))
        self.assertEqual(set(ns), {"/hapi_server_manager", "/eskf", "/surface_motion", "/surface"})
        self.assertEqual(remaps(ns["/eskf"])["~landmarks"], "/stereo_frontend/landmarks")
        # The surface motion reads the ESKF's private outputs and the front end's image flow.
        sm = remaps(ns["/surface_motion"])
        self.assertIn("hapi_eskf/SurfaceMotionNodelet", ns["/surface_motion"].args)
        self.assertEqual((sm["odom"], sm["map"], sm["flow"]), ("/eskf/odom", "/eskf/map", "/imaging_flow/flow"))
        self.assertEqual(set(self.check_runnable(load("server.launch", "surface_motion:=false", "surface:=false"))),
                         {"/hapi_server_manager", "/eskf"})
        # The surface: the robot's dense depth, the imaging camera (default the left one) and the filter's path,
        # in the filter's TF parent frame; a scene's profile is loaded on request only.
        sf = remaps(ns["/surface"])
        self.assertIn("hapi_surface/SurfaceNodelet", ns["/surface"].args)
        self.assertEqual((sf["depth"], sf["depth_camera_info"], sf["path"]),
                         ("/dense_depth/depth", "/dense_depth/camera_info", "/eskf/path"))
        self.assertEqual((sf["imaging/image"], sf["imaging/camera_info"]),
                         ("/stereo/left/image_raw", "/stereo/left/camera_info"))
        cfg = load("server.launch")
        self.assertEqual(cfg.params["/surface/world_frame"].value, "map")
        # The surface's own motion: the config's unless asked for.
        self.assertIs(cfg.params["/eskf/scene_motion"].value, False)
        self.assertIs(load("server.launch", "scene_motion:=true").params["/eskf/scene_motion"].value, True)
        self.assertNotIn("/surface/voxel_size", cfg.params)
        globe = load("server.launch", "surface_config:=" + os.path.join(LAUNCH, "..", "config", "surface_globe.yaml"))
        self.assertGreater(globe.params["/surface/voxel_size"].value, 0.0005)
        ns = self.check_runnable(load("server.launch", "rviz:=true"))
        self.assertIn("/rviz", ns)
        self.assertIn("hapi.rviz", ns["/rviz"].args)

    def test_all_in_one_single_manager(self):
        ns = self.check_runnable(load("all_in_one.launch"))
        managers = [n for n in ns.values() if n.args == "manager"]
        self.assertEqual(len(managers), 1, "one shared nodelet manager")
        fe, be = ns["/stereo_frontend"], ns["/eskf"]
        self.assertIn("hapi_frontend/StereoFrontendNodelet", fe.args)
        self.assertIn("hapi_eskf/EskfNodelet", be.args)
        self.assertEqual(fe.args.split()[2], be.args.split()[2], "front and back end in the same manager")
        # The front end's output is the back end's input.
        self.assertEqual(remaps(fe)["~landmarks"], remaps(be)["~landmarks"])
        # The imaging camera is the left camera by default; its flow (/imaging_flow/flow) feeds the surface motion.
        flow, sm = ns["/imaging_flow"], ns["/surface_motion"]
        self.assertIn("hapi_frontend/ImagingFlowNodelet", flow.args)
        self.assertEqual(remaps(flow)["image"], "/stereo/left/image_raw")
        self.assertEqual(remaps(sm)["flow"], "/imaging_flow/flow")
        self.assertEqual(remaps(sm)["imaging/camera_info"], "/stereo/left/camera_info")
        self.assertNotIn("/rviz", ns, "headless by default")
        # Dense depth on the front end's stereo topics, in the shared manager, feeding the surface.
        dd, sf = ns["/dense_depth"], ns["/surface"]
        self.assertIn("hapi_surface/DenseDepthNodelet", dd.args)
        self.assertEqual(dd.args.split()[2], be.args.split()[2])
        self.assertEqual({k: v for k, v in remaps(dd).items()}, {k: v for k, v in remaps(fe).items() if k != "~landmarks"})
        self.assertEqual(remaps(sf)["depth"], "/dense_depth/depth")
        imaging = nodes(load("all_in_one.launch", "imaging_image:=/imaging/image_raw",
                             "imaging_info:=/imaging/camera_info"))
        self.assertEqual(remaps(imaging["/surface"])["imaging/image"], "/imaging/image_raw")
        self.assertEqual(remaps(imaging["/surface"])["imaging/camera_info"], "/imaging/camera_info")
        off = nodes(load("all_in_one.launch", "dense_depth:=false", "surface:=false"))
        self.assertNotIn("/dense_depth", off)
        self.assertNotIn("/surface", off)

    def test_all_in_one_two_managers(self):
        ns = self.check_runnable(load("all_in_one.launch", "single_manager:=false", "rviz:=true"))
        self.assertEqual(len([n for n in ns.values() if n.args == "manager"]), 2)
        self.assertNotEqual(ns["/stereo_frontend"].args.split()[2], ns["/eskf"].args.split()[2])
        self.assertIn("/rviz", ns)

    def test_live(self):
        ns = self.check_runnable(load("live.launch", "left_image:=/cam0/image_raw", "left_info:=/cam0/camera_info",
                                      "right_image:=/cam1/image_raw", "right_info:=/cam1/camera_info",
                                      "imu_topic:=/imu0", "approximate_sync:=true"))
        self.assertEqual(set(ns), {"/hapi_manager", "/stereo_frontend", "/eskf"})
        fe, be = ns["/stereo_frontend"], ns["/eskf"]
        self.assertEqual(fe.args.split()[2], be.args.split()[2], "front and back end in the same manager")
        self.assertEqual(remaps(fe)["~landmarks"], remaps(be)["~landmarks"])
        fe_remaps = remaps(fe)
        self.assertIn("/cam0/image_raw", fe_remaps.values())
        self.assertIn("/cam1/camera_info", fe_remaps.values())

    def test_replay(self):
        cfg = load("replay.launch", "bag:=/data/globe.bag", "evaluate:=true", "eval_output:=/tmp/r.yaml",
                   "record_diagnostics:=/tmp/d.bag")
        ns = self.check_runnable(cfg)
        self.assertIs(cfg.params["/use_sim_time"].value, True)
        play = ns["/player"]
        self.assertEqual((play.package, play.type), ("rosbag", "play"))
        self.assertIn("--clock", play.args.split())
        self.assertIn("/data/globe.bag", play.args.split())
        self.assertTrue(ns["/evaluate_run"].required, "the evaluator ends the run")
        self.assertIn("/diagnostics", ns["/record_diagnostics"].args.split())
        self.assertIn("/ground_truth_tf", ns)
        plain = nodes(load("replay.launch", "bag:=/data/globe.bag"))
        self.assertNotIn("/evaluate_run", plain)
        self.assertNotIn("/record_diagnostics", plain)
        self.assertIn("--loop", nodes(load("replay.launch", "bag:=/b.bag", "loop:=true"))["/player"].args.split())
        self.assertNotIn("--pause", plain["/player"].args.split())
        # paused:=true (the rviz screenshot check resumes the player by its service)
        self.assertIn("--pause", nodes(load("replay.launch", "bag:=/b.bag", "paused:=true"))["/player"].args.split())

    def test_replay_requires_bag(self):
        with self.assertRaises(Exception):
            load("replay.launch")

    def test_distributed_machines(self):
        cfg = load("distributed.launch", "robot_address:=10.0.0.2", "robot_env_loader:=/r/env_loader.sh",
                   "server_env_loader:=/s/env_loader.sh", "rviz:=true")
        ns = self.check_runnable(cfg)
        where = {name: cfg.machines[n.machine_name].address for name, n in ns.items()}
        self.assertEqual(where["/robot_manager"], "10.0.0.2")
        self.assertEqual(where["/stereo_frontend"], "10.0.0.2")
        self.assertEqual(where["/server_manager"], "localhost")
        self.assertEqual(where["/eskf"], "localhost")
        self.assertEqual(where["/rviz"], "localhost")
        # Only the depth keyframes cross the link: dense depth on the robot, the surface on the server.
        self.assertEqual(where["/dense_depth"], "10.0.0.2")
        self.assertEqual(where["/surface"], "localhost")
        self.assertEqual(cfg.machines[ns["/stereo_frontend"].machine_name].env_loader, "/r/env_loader.sh")
        self.assertEqual(cfg.machines[ns["/eskf"].machine_name].env_loader, "/s/env_loader.sh")
        # Each side has its own manager: only landmarks cross the network.
        self.assertEqual(ns["/stereo_frontend"].args.split()[2], "robot_manager")
        self.assertEqual(ns["/eskf"].args.split()[2], "server_manager")


if __name__ == "__main__":
    import rosunit
    rosunit.unitrun(PKG, "launch_files", LaunchFilesTest)
