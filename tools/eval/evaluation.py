"""Trajectory and map metrics for the HAPI pipeline (pure numpy, no ROS).

Used by tools/eval/evaluate_run.py (live, in launch files and rostests) and by
its unit test. Conventions: poses are (position p [m], quaternion q = (x, y, z,
w)) of the left camera optical frame; the filter's world frame and the ground
truth's "map" frame differ by an unknown rigid transform, found by a least
squares fit (Umeyama, no scale: stereo gives metric scale).
"""
import numpy as np


def quat_to_rot(q):
    x, y, z, w = q
    n = np.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def align_rigid(est, ref):
    """Rotation R and translation t minimising sum |R est_i + t - ref_i|^2.

    est, ref: (N, 3) arrays of corresponding points, N >= 3 (Umeyama 1991,
    without scale).
    """
    est = np.asarray(est, dtype=float)
    ref = np.asarray(ref, dtype=float)
    if est.shape != ref.shape or est.shape[0] < 3:
        raise ValueError("need at least 3 corresponding points")
    mu_e = est.mean(axis=0)
    mu_r = ref.mean(axis=0)
    cov = (ref - mu_r).T @ (est - mu_e) / est.shape[0]
    u, _, vt = np.linalg.svd(cov)
    d = np.eye(3)
    if np.linalg.det(u) * np.linalg.det(vt) < 0:
        d[2, 2] = -1.0
    r = u @ d @ vt
    t = mu_r - r @ mu_e
    return r, t


def associate(est_stamps, ref_stamps, max_dt):
    """Index pairs (i, j) matching each estimate to the nearest reference stamp."""
    ref_stamps = np.asarray(ref_stamps, dtype=float)
    order = np.argsort(ref_stamps)
    sorted_ref = ref_stamps[order]
    pairs = []
    for i, t in enumerate(est_stamps):
        k = np.searchsorted(sorted_ref, t)
        best = None
        for c in (k - 1, k):
            if 0 <= c < len(sorted_ref):
                dt = abs(sorted_ref[c] - t)
                if dt <= max_dt and (best is None or dt < best[1]):
                    best = (c, dt)
        if best is not None:
            pairs.append((i, int(order[best[0]])))
    return pairs


def path_length(points):
    points = np.asarray(points, dtype=float)
    if len(points) < 2:
        return 0.0
    return float(np.sum(np.linalg.norm(np.diff(points, axis=0), axis=1)))


def trajectory_error(est_positions, ref_positions):
    """ATE after rigid alignment: dict with rmse, max, aligned R, t."""
    r, t = align_rigid(est_positions, ref_positions)
    aligned = (r @ np.asarray(est_positions, dtype=float).T).T + t
    err = np.linalg.norm(aligned - np.asarray(ref_positions, dtype=float), axis=1)
    return {"rmse": float(np.sqrt(np.mean(err ** 2))), "max": float(err.max()), "R": r, "t": t}


def sphere_error(points, r, t, centre, radius):
    """RMS distance [m] of aligned points to the sphere surface."""
    pts = np.asarray(points, dtype=float)
    if pts.size == 0:
        raise ValueError("empty map")
    aligned = (r @ pts.T).T + t
    d = np.linalg.norm(aligned - np.asarray(centre, dtype=float), axis=1) - radius
    return float(np.sqrt(np.mean(d ** 2))), float(np.median(np.abs(d)))
