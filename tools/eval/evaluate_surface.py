#!/usr/bin/python3
"""Scores a reconstructed surface mesh (PLY) against the simulator's truth
(surface_metrics.py): accuracy, completeness and the perfusion pattern's
registration.

  evaluate_surface.py --mesh surface.ply --bag sim.bag [--keyframe-rate 2] [--json out.json]
  evaluate_surface.py --mesh surface.ply --scene scene.yaml [--trajectory gt.tum --camera fx,fy,cx,cy,w,h]
                      [--perfusion perfusion.yaml]

With --bag the truth comes from the simulator's recording: /ground_truth/scene,
/ground_truth/perfusion (make_sim_bag --imaging-content perfusion),
/ground_truth/pose (the left camera in world per stereo frame) and
/stereo/left/camera_info. The mesh is taken to be in the truth's world frame
unless --t-world-mesh gives the 16 numbers (row-major) of the transform.
"""
import argparse
import json
import sys

import numpy as np

import scene_geometry as sg
import surface_metrics as sm
import trajectory_io as tio
from evaluation import quat_to_rot


def read_mesh(path, value_property="value"):
    """(vertices (N, 3), faces (F, 3), values (N,) or None) of a PLY mesh."""
    ply = tio.read_ply(path)
    v = ply.get("vertex", {})
    vertices = tio.read_ply_points(path)
    faces = ply.get("face", {}).get("vertex_indices", [])
    if any(len(f) != 3 for f in faces):
        raise ValueError(f"{path}: only triangle faces are scored")
    faces = np.array(faces, dtype=np.int64).reshape(-1, 3)
    values = np.asarray(v[value_property], dtype=float) if value_property in v else None
    return vertices, faces, values


def pose_matrix(p, q_xyzw):
    T = np.eye(4)
    T[:3, :3] = quat_to_rot(q_xyzw)
    T[:3, 3] = p
    return T


def camera_from_info(msg):
    """(fx, fy, cx, cy, width, height) of a sensor_msgs/CameraInfo: the pinhole
    that completeness casts its rays through."""
    return (msg.K[0], msg.K[4], msg.K[2], msg.K[5], msg.width, msg.height)


def every_nth_in_time(stamps, rate):
    """Indices of the keyframes a gate of `rate` Hz takes (the first, then the
    first at least 1/rate later): DenseDepthKeyframeGate's rule."""
    keep, last = [], None
    for i, t in enumerate(stamps):
        if last is None or t - last >= 1.0 / rate - 1e-9:
            keep.append(i)
            last = t
    return keep


def truth_from_bag(path):
    """(surfaces, pattern or None, stamps, poses, camera) of a simulator bag."""
    import rosbag
    surfaces, pattern, stamps, poses, camera = None, None, [], [], None
    with rosbag.Bag(path) as b:
        for topic, m, _ in b.read_messages(topics=["/ground_truth/scene", "/ground_truth/perfusion",
                                                    "/ground_truth/pose", "/stereo/left/camera_info"]):
            if topic == "/ground_truth/scene" and surfaces is None:
                surfaces = sg.parse_scene(m.data)[1]
            elif topic == "/ground_truth/perfusion" and pattern is None:
                pattern = sm.parse_perfusion(m.data)
            elif topic == "/ground_truth/pose":
                o, p = m.pose.orientation, m.pose.position
                stamps.append(m.header.stamp.to_sec())
                poses.append(pose_matrix([p.x, p.y, p.z], [o.x, o.y, o.z, o.w]))
            elif topic == "/stereo/left/camera_info" and camera is None:
                camera = camera_from_info(m)
    if surfaces is None:
        raise ValueError(f"{path} has no /ground_truth/scene")
    return surfaces, pattern, stamps, poses, camera


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesh", required=True, help="PLY mesh (vertices, triangle faces, optional per-vertex value)")
    ap.add_argument("--bag", help="simulator bag with the truth")
    ap.add_argument("--scene", help="scene YAML (/ground_truth/scene)")
    ap.add_argument("--perfusion", help="perfusion pattern YAML (/ground_truth/perfusion)")
    ap.add_argument("--trajectory", help="TUM trajectory of the left camera in world (ground truth)")
    ap.add_argument("--camera", help="fx,fy,cx,cy,width,height of the left camera")
    ap.add_argument("--keyframe-rate", type=float, default=2.0, help="Hz, keyframes counted for 'seen' (default 2)")
    ap.add_argument("--depth-range", default="%g,%g" % sm.DEFAULT_DEPTH_RANGE, help="m, near,far of the depth keyframes")
    ap.add_argument("--value-property", default="value", help="PLY vertex property of the projected value")
    ap.add_argument("--t-world-mesh", help="16 comma-separated numbers: the mesh frame in world")
    ap.add_argument("--json", help="write the figures here too")
    a = ap.parse_args(argv)
    vertices, faces, values = read_mesh(a.mesh, a.value_property)
    pattern, stamps, poses, camera = None, [], [], None
    if a.bag:
        surfaces, pattern, stamps, poses, camera = truth_from_bag(a.bag)
    elif a.scene:
        with open(a.scene) as f:
            surfaces = sg.parse_scene(f.read())[1]
    else:
        ap.error("--bag or --scene is required")
    if a.perfusion:
        with open(a.perfusion) as f:
            pattern = sm.parse_perfusion(f.read())
    if a.trajectory:
        tr = tio.read_trajectory(a.trajectory)
        stamps, poses = list(tr["t"]), [pose_matrix(p, q) for p, q in zip(tr["p"], tr["q"])]
    if a.camera:
        camera = tuple(float(x) for x in a.camera.split(","))
    poses = [poses[i] for i in every_nth_in_time(stamps, a.keyframe_rate)] if poses else None
    T = np.array([float(x) for x in a.t_world_mesh.split(",")]).reshape(4, 4) if a.t_world_mesh else None
    near, far = (float(x) for x in a.depth_range.split(","))
    result = sm.evaluate_surface(vertices, faces, surfaces, values, pattern, poses, camera, (near, far), T)
    for k, v in result.items():
        print(f"{k}: {v:.3f}" if isinstance(v, float) else f"{k}: {v}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(result, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
