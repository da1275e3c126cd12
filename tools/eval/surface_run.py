"""The 3D surface of a pipeline run (hapi_surface/SurfaceNodelet), for
evaluate_run.py: at the end of the run the nodelet's ~save_surface writes
mesh.ply next to the report; the mesh is scored against the simulator's truth
(surface_metrics.py: accuracy, completeness, the perfusion pattern's
registration) and drawn as mesh.png (render_mesh.py).

The mesh is in the filter's `map` frame; it is moved into the truth's world
frame by the same rigid alignment as the ATE and the map error
(run_analysis.analyse's series["alignment"]), so a drift of the whole
trajectory is not counted as a surface error, as it is not in the map error.
Given the estimated trajectory, the mesh is also scored in the alignment of
whole poses (surface_metrics.pose_alignment: `pose_aligned`), which fixes
the world's rotation that the positions of a hand-held scan leave loose.
Completeness counts the true surface seen by the left camera at the ground-
truth poses at the dense depth's keyframe rate (its ~rate parameter) and in
the depth range that both the dense depth and the surface fuse
(keyframe_settings).
"""
import os

import numpy as np
import rospy

import evaluation
import trajectory_metrics
from sensor_msgs.msg import CameraInfo
from std_msgs.msg import String

import evaluate_surface
import render_mesh
import surface_metrics


class SurfaceCollector:
    """Subscribes to the truth the surface's score needs; save_and_score()
    at the end of the run. Raises ImportError without hapi_msgs' Python
    services (the caller then reports the surface as not evaluated)."""

    def __init__(self):
        from hapi_msgs.srv import SaveSurface
        self.srv_type = SaveSurface
        self.service = rospy.get_param("~surface_service", "/surface/save_surface")
        self.depth_ns = rospy.get_param("~dense_depth_ns", "/dense_depth")
        self.surface_ns = self.service.rsplit("/", 1)[0]
        self.perfusion_text = None
        self.camera = None
        # Estimated and true poses of one frame share its stamp.
        self.max_pose_dt = 0.005
        rospy.Subscriber(rospy.get_param("~perfusion_topic", "/ground_truth/perfusion"), String,
                         self.on_perfusion, queue_size=2)
        rospy.Subscriber(rospy.get_param("~camera_info_topic", "/stereo/left/camera_info"), CameraInfo,
                         self.on_camera_info, queue_size=2)
        # The ~mesh marker, watched only when asked (a test): the nodelet meshes
        # every mesh_period while anyone subscribes, which costs the main job CPU.
        self.mesh_messages, self.mesh_triangles = 0, 0
        mesh_topic = rospy.get_param("~surface_mesh_topic", "")
        if mesh_topic:
            rospy.Subscriber(mesh_topic, rospy.AnyMsg, self.on_mesh, queue_size=1)

    def on_mesh(self, raw):
        """visualization_msgs/Marker, decoded from the definition the publisher
        sends (Debian ships no Python visualization_msgs)."""
        import genpy.dynamic
        header = raw._connection_header
        cls = genpy.dynamic.generate_dynamic(header["type"], header["message_definition"])[header["type"]]
        msg = cls().deserialize(raw._buff)
        if msg.type == cls.TRIANGLE_LIST and msg.points:
            self.mesh_messages += 1
            self.mesh_triangles = len(msg.points) // 3

    def on_perfusion(self, msg):
        self.perfusion_text = msg.data

    def on_camera_info(self, msg):
        if self.camera is None:
            self.camera = evaluate_surface.camera_from_info(msg)

    def save(self, path, timeout):
        """{saved, vertices, faces} or {error} of one ~save_surface call."""
        try:
            rospy.wait_for_service(self.service, timeout=timeout)
            r = rospy.ServiceProxy(self.service, self.srv_type)(path=path)
        except (rospy.ROSException, rospy.ServiceException) as e:
            return {"error": f"{self.service}: {e}"}
        if not r.success:
            return {"error": f"{self.service}: {r.message}"}
        return {"mesh": os.path.basename(path), "vertices": int(r.vertices), "faces": int(r.faces)}

    def keyframe_settings(self):
        """(keyframe rate [Hz], (near, far) [m] or None): the dense depth's
        rate, and the depth range both the dense depth and the surface fuse
        (the narrower of the two where a profile sets them; None: neither
        does, evaluate_surface's default, the nodelets' defaults)."""
        rate = float(rospy.get_param(self.depth_ns + "/rate", 2.0))
        nodes = (self.depth_ns, self.surface_ns)
        near = [float(rospy.get_param(n + "/min_depth")) for n in nodes if rospy.has_param(n + "/min_depth")]
        far = [float(rospy.get_param(n + "/max_depth")) for n in nodes if rospy.has_param(n + "/max_depth")]
        if not near and not far:
            return rate, None
        default_near, default_far = surface_metrics.DEFAULT_DEPTH_RANGE
        return rate, (max(near + [default_near]), min(far + [default_far]))

    def score(self, path, alignment, surfaces, gt):
        """The truth's figures of the saved mesh (surface_metrics.evaluate_surface)."""
        vertices, faces, values = evaluate_surface.read_mesh(path)
        if not len(faces):
            return {"error": "the surface is empty (no keyframe fused?)"}
        R, t = alignment
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = R, t
        rate, depth_range = self.keyframe_settings()
        keep = evaluate_surface.every_nth_in_time(list(gt["t"]), rate)
        poses = [evaluate_surface.pose_matrix(gt["p"][i], gt["q"][i]) for i in keep]
        pattern = surface_metrics.parse_perfusion(self.perfusion_text) if self.perfusion_text else None
        kwargs = {"depth_range": depth_range} if depth_range else {}
        out = surface_metrics.evaluate_surface(vertices, faces, surfaces, values, pattern,
                                               poses if self.camera else None, self.camera,
                                               T_world_mesh=T, **kwargs)
        out["keyframe_rate_hz"] = rate
        return out

    def pose_aligned(self, path, est, gt, scene, alignment):
        """The score in the alignment of whole poses (or {error}), and the
        angle between its rotation and the positions-only `alignment`'s."""
        pairs = evaluation.associate(est["t"], gt["t"], self.max_pose_dt)
        if len(pairs) < 3:
            return {"error": "fewer than 3 estimated poses match the truth"}
        ie, ig = np.array([i for i, _ in pairs]), np.array([j for _, j in pairs])
        R, t = surface_metrics.pose_alignment(trajectory_metrics.rotations_from_quats(np.asarray(est["q"])[ie]),
                                              np.asarray(est["p"])[ie],
                                              trajectory_metrics.rotations_from_quats(np.asarray(gt["q"])[ig]),
                                              np.asarray(gt["p"])[ig])
        out = self.score(path, (R, t), scene[1], gt)
        out["angle_to_ate_alignment_deg"] = float(np.degrees(evaluation.rotation_angle(R.T @ alignment[0])))
        return {k: v for k, v in out.items() if k != "keyframe_rate_hz"}

    def save_and_score(self, out_dir, alignment, scene, gt, diag, timeout=10.0, est=None):
        """The report's `surface` section: the mesh saved, its score, its
        picture, and the nodelet's keyframe counts. Never raises: what is
        missing is said in `error` or `picture_missing`."""
        path = os.path.join(out_dir, "mesh.ply")
        if os.path.exists(path):
            os.remove(path)  # an old run's mesh must never be scored as this one's
        rep = self.save(path, timeout)
        status = next((v for k, v in diag.items() if k.split(":")[-1].strip() == "surface"), {})
        depth = next((v for k, v in diag.items() if k.split(":")[-1].strip() == "dense depth"), {})
        if "published" in depth:  # the depth keyframes that crossed the robot-server link
            rep["depth_keyframes_published"] = int(float(depth["published"]))
        for key, name in (("keyframes", "keyframes_fused"), ("keyframes stored", "keyframes_stored"),
                          ("imaging projected", "imaging_frames_projected"), ("integration", "integration"),
                          ("keyframes before the filter settled", "keyframes_unsettled"),
                          ("early keyframes registered and fused", "early_keyframes_fused"),
                          ("early keyframes discarded", "early_keyframes_discarded"),
                          ("keyframes waiting for a settled filter", "keyframes_waiting")):
            if key in status:
                rep[name] = status[key] if name == "integration" else int(float(status[key]))
        # The keyframes that waited for a settled filter and were fused then
        # count as fused too.
        if "keyframes_fused" in rep:
            rep["keyframes_fused"] += rep.get("early_keyframes_fused", 0)
        if rospy.get_param("~surface_mesh_topic", ""):
            rep["mesh_messages"], rep["mesh_marker_triangles"] = self.mesh_messages, self.mesh_triangles
        if "error" in rep:
            return rep
        if alignment is None or scene is None:
            rep["not_scored"] = "no ground truth (trajectory alignment or scene geometry)"
        else:
            try:
                rep.update(self.score(path, alignment, scene[1], gt))
                if est is not None and len(est["t"]):
                    rep["pose_aligned"] = self.pose_aligned(path, est, gt, scene, alignment)
            except (ValueError, KeyError, IndexError) as e:
                rep["score_error"] = str(e)
        try:
            rep["picture"] = os.path.basename(render_mesh.render_file(path, os.path.join(out_dir, "mesh.png")))
        except Exception as e:  # a picture must never cost the report
            rep["picture_missing"] = f"rendering failed: {e}"
        return rep
