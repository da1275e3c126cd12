"""One evaluation of an estimate against its ground truth: the report fields
and the time series the plots draw (pure numpy, no ROS).

Shared by the live evaluator (evaluate_run.py) and the offline CLI
(evaluate.py) so both report the same metrics under the same names. A
trajectory is a dict: t (N,) [s], p (N, 3) [m], q (N, 4) (x, y, z, w) camera ->
world, optionally cov (N, 6, 6) (odometry pose covariance) and twist (N, 6)
(linear, angular in the camera frame). gt_twist: {t (M,), twist (M, 6)}, the
true twist in the same camera frame (/ground_truth/odometry).
"""
import numpy as np
import yaml

import evaluation as ev
import scene_geometry
import trajectory_metrics as tm

RPE_DELTA_S = 1.0
# A truth whose largest distance from its first pose (net travel) stays below
# this is a device standing still. Its path length is no criterion: a real
# ground truth's jitter alone adds centimetres of path (EuRoC V1_01's 20 Hz
# Vicon jitter: ~17 mm over 4.7 s for 2.3 mm of net travel). Standing still,
# ATE % of the distance means nothing and an SE(3) alignment of poses at one
# point leaves the rotation free: the run is scored by its drift instead.
STANDSTILL_MAX_NET_TRAVEL_M = 0.005
# A standing device's estimate "did not wander" (the main job's pass/fail,
# pipeline_summary.py and evaluate_run.py): it stays within 1 cm and 1 deg of
# its first pose, a tenth of the ATE bound on a 10 cm hand-held sweep.
STANDSTILL_MAX_DRIFT_M = 0.01
STANDSTILL_MAX_DRIFT_DEG = 1.0


def net_travel(p):
    """Largest distance [m] of positions (N, 3) from the first one."""
    p = np.asarray(p, dtype=float).reshape(-1, 3)
    return float(np.max(np.linalg.norm(p - p[0], axis=1))) if len(p) else 0.0


def is_standstill(truth_p):
    return net_travel(truth_p) < STANDSTILL_MAX_NET_TRAVEL_M


def drift(p, q):
    """(largest distance [m], largest rotation [deg]) of poses from the first one."""
    r = tm.rotations_from_quats(q)
    return net_travel(p), float(np.degrees(max(ev.rotation_angle(r[0].T @ x) for x in r)))


def match(est, gt, max_dt, interpolate=False):
    """(estimate indices, truth positions, truth rotations)."""
    if interpolate:
        r_gt = tm.rotations_from_quats(gt["q"])
        idx, p, r = tm.interpolate_poses(gt["t"], gt["p"], r_gt, est["t"], max_gap=max_dt)
        return idx, p, r
    pairs = ev.associate(est["t"], gt["t"], max_dt)
    ie = np.array([i for i, _ in pairs], dtype=int)
    ig = np.array([j for _, j in pairs], dtype=int)
    return ie, np.asarray(gt["p"])[ig].reshape(-1, 3), tm.rotations_from_quats(np.asarray(gt["q"])[ig])


def map_gauge(e_p, e_r, g_p, g_r, se3, map_points, anchor=None):
    """(R, t, name) that carries the estimate's world, and its map, into the
    truth's. The trajectory's SE(3) alignment when the trajectory fixes its
    rotation; else the estimate tied to the truth at `anchor` (default: the
    first matched pose), "anchored".

    The alignment's rotation is fixed by the trajectory's spread across its
    least-spread axes: with positions of RMS error e spread s_2 (the second
    singular value of the centred truth, RMS) over N poses, its error is
    about e / (s_2 sqrt(N)), and a map point at a distance L from the
    trajectory moves by L times that. When L > s_2 sqrt(N) that exceeds the
    trajectory's own error e, and the score would measure the alignment
    rather than the map: a device held still in front of the skin (tremor
    only, s_2 ~ 3 mm, N = 70, L ~ 0.3 m) scored 1.2-2.6 cm on the same
    run's map that way."""
    g_p = np.asarray(g_p, dtype=float).reshape(-1, 3)
    spread = np.linalg.svd(g_p - g_p.mean(axis=0), compute_uv=False) / np.sqrt(len(g_p))
    pts = np.asarray(map_points, dtype=float).reshape(-1, 3)
    lever = float(np.sqrt(np.mean(np.sum((pts - np.mean(e_p, axis=0)) ** 2, axis=1))))
    if spread[1] * np.sqrt(len(g_p)) >= lever:
        return se3["R"], se3["t"], "se3"
    if anchor is None:
        anchor = (e_p[0], e_r[0], g_p[0], g_r[0])
    return tm.anchor_transform(anchor) + ("anchored",)


def analyse(est, gt, max_dt, interpolate=False, scene=None, map_points=None, gt_twist=None, anchor=None):
    """(report dict, series dict). Report keys are flat, SI units in the names.

    NEES (with est["cov"]): tied to the truth at `anchor` (est_p0, est_r0,
    ref_p0, ref_r0; trajectory_metrics.anchored_pose_nees) when given, at
    the first matched pose on a standstill, else after the SE(3) alignment.
    A standstill (is_standstill) reports the estimate's drift from its first
    pose instead of ATE % of the distance and the aligned rotation error."""
    rep, series = {}, {}
    ie, g_p, g_r = match(est, gt, max_dt, interpolate)
    rep["poses_compared"] = int(len(ie))
    if len(ie) < 3:
        return rep, series
    e_t = np.asarray(est["t"], dtype=float)[ie]
    e_p = np.asarray(est["p"], dtype=float)[ie]
    e_r = tm.rotations_from_quats(np.asarray(est["q"])[ie])
    se3 = tm.ate(e_p, g_p)
    sim3 = tm.ate(e_p, g_p, with_scale=True)
    dist = ev.path_length(g_p)
    rot = tm.rotation_errors_deg(e_r, g_r, se3["R"])
    rep.update({
        "ate_rmse_m": se3["rmse"], "ate_max_m": se3["max"], "ate_median_m": se3["median"],
        "distance_travelled_m": dist,
        "ate_fraction_of_distance": se3["rmse"] / dist if dist > 0 else float("inf"),
        "ate_sim3_rmse_m": sim3["rmse"], "sim3_scale": sim3["s"],
        "rotation_rmse_deg": float(np.sqrt(np.mean(rot ** 2))), "rotation_max_deg": float(rot.max()),
    })
    series.update({"t": e_t - e_t[0], "est_aligned": se3["aligned"], "truth": g_p, "alignment": (se3["R"], se3["t"]),
                   "position_error_m": se3["errors"], "rotation_error_deg": rot})
    if is_standstill(g_p):
        d_m, d_deg = drift(est["p"], est["q"])
        rep.update({"standstill": True, "truth_net_travel_m": net_travel(g_p), "standstill_drift_m": d_m,
                    "standstill_rotation_drift_deg": d_deg})
        for key in ("ate_fraction_of_distance", "rotation_rmse_deg", "rotation_max_deg"):
            del rep[key]
        if anchor is None:
            anchor = (e_p[0], e_r[0], g_p[0], g_r[0])
        # The plot shows what the report scores: the SE(3) alignment of a
        # trajectory that barely moves leaves the rotation free.
        a_p, a_r, _ = tm.anchored_errors(e_p, e_r, g_p, g_r, anchor)
        series.update({"position_error_m": np.linalg.norm(a_p, axis=1),
                       "rotation_error_deg": np.degrees(np.linalg.norm(a_r, axis=1)),
                       "error_title": "error with the estimate tied to the truth at its first pose (standing still)"})
    rpe_t, rpe_r = tm.rpe(e_t, e_p, e_r, g_p, g_r, delta=RPE_DELTA_S)
    if len(rpe_t):
        rep.update({"rpe_1s_translation_rmse_m": float(np.sqrt(np.mean(rpe_t ** 2))),
                    "rpe_1s_rotation_rmse_deg": float(np.sqrt(np.mean(rpe_r ** 2))), "rpe_1s_pairs": int(len(rpe_t))})
    if est.get("cov") is not None:
        cov = np.asarray(est["cov"], dtype=float)[ie]
        if anchor is not None:
            n_p, n_r = tm.anchored_pose_nees(e_p, e_r, g_p, g_r, cov, anchor)
            rep["nees_anchored"] = True
        else:
            n_p, n_r = tm.pose_nees(se3["aligned"], g_p, e_r, g_r, se3["R"], cov)
        for key, vals in (("nees_position", n_p), ("nees_rotation", n_r)):
            summary = tm.nees_summary(vals)
            if summary is not None:
                rep[key] = summary
                series[key] = vals
    if est.get("twist") is not None and gt_twist is not None and len(gt_twist["t"]):
        pairs = ev.associate(est["t"], gt_twist["t"], max_dt)
        if pairs:
            e_tw = np.asarray(est["twist"], dtype=float)[[i for i, _ in pairs]]
            g_tw = np.asarray(gt_twist["twist"], dtype=float)[[j for _, j in pairs]]
            w_rms, v_rms = tm.velocity_errors(e_tw, g_tw)
            rep.update({"angular_velocity_rms_rad_s": w_rms, "linear_velocity_rms_m_s": v_rms,
                        "velocity_samples": len(pairs)})
    if map_points is not None and len(map_points) > 0:
        rep["map_points"] = int(len(map_points))
        if scene is not None:
            name, surfaces = scene
            r_map, t_map, rep["map_alignment"] = map_gauge(e_p, e_r, g_p, g_r, se3, map_points, anchor)
            rms, med = scene_geometry.map_error(map_points, r_map, t_map, surfaces)
            rep["map_rms_to_surface_m"], rep["map_median_abs_to_surface_m"] = rms, med
            rep["scene"] = name
            if name == "globe":  # the globe bags' historic field names (system tests, summary)
                rep["map_rms_to_sphere_m"], rep["map_median_abs_to_sphere_m"] = rms, med
    return rep, series


def write_report(path, report, text, markdown=None):
    """An evaluation tool's results: the report as YAML at path, the table
    text as markdown (when asked) and on stdout."""
    with open(path, "w") as f:
        yaml.safe_dump(to_plain(report), f, sort_keys=True)
    if markdown:
        with open(markdown, "w") as f:
            f.write(text + "\n")
    print(text)


def to_plain(x):
    """numpy scalars inside dicts/lists -> Python values (for yaml.safe_dump)."""
    if isinstance(x, dict):
        return {k: to_plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [to_plain(v) for v in x]
    return x.item() if isinstance(x, np.generic) else x
