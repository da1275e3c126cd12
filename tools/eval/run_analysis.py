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

import evaluation as ev
import scene_geometry
import trajectory_metrics as tm

RPE_DELTA_S = 1.0


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


def analyse(est, gt, max_dt, interpolate=False, scene=None, map_points=None, gt_twist=None):
    """(report dict, series dict). Report keys are flat, SI units in the names."""
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
    series.update({"t": e_t - e_t[0], "est_aligned": se3["aligned"], "truth": g_p,
                   "position_error_m": se3["errors"], "rotation_error_deg": rot})
    rpe_t, rpe_r = tm.rpe(e_t, e_p, e_r, g_p, g_r, delta=RPE_DELTA_S)
    if len(rpe_t):
        rep.update({"rpe_1s_translation_rmse_m": float(np.sqrt(np.mean(rpe_t ** 2))),
                    "rpe_1s_rotation_rmse_deg": float(np.sqrt(np.mean(rpe_r ** 2))), "rpe_1s_pairs": int(len(rpe_t))})
    if est.get("cov") is not None:
        cov = np.asarray(est["cov"], dtype=float)[ie]
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
            rms, med = scene_geometry.map_error(map_points, se3["R"], se3["t"], surfaces)
            rep["map_rms_to_surface_m"], rep["map_median_abs_to_surface_m"] = rms, med
            rep["scene"] = name
            if name == "globe":  # the globe bags' historic field names (system tests, summary)
                rep["map_rms_to_sphere_m"], rep["map_median_abs_to_sphere_m"] = rms, med
    return rep, series


def to_plain(x):
    """numpy scalars inside dicts/lists -> Python values (for yaml.safe_dump)."""
    if isinstance(x, dict):
        return {k: to_plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [to_plain(v) for v in x]
    return x.item() if isinstance(x, np.generic) else x
