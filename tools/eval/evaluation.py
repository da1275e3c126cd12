"""Geometry and alignment primitives of the HAPI evaluation (pure numpy, no ROS).

Used by tools/eval/evaluate_run.py (live, in launch files and rostests), by
the offline tools/eval/evaluate.py (through trajectory_metrics.py) and by the
unit tests. Conventions: poses are (position p [m], quaternion q = (x, y, z,
w)) of the left camera optical frame; the filter's world frame and the ground
truth's "map" frame differ by an unknown rigid transform, found by a least
squares fit (Umeyama 1991; without scale for the reported ATE, since stereo
gives metric scale; with scale only as the Sim(3) figure reported next to it).
"""
import numpy as np

import scene_geometry  # same folder: the callers put it on sys.path


def quat_to_rot(q):
    x, y, z, w = q
    n = np.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def rot_to_quat(r):
    """(x, y, z, w) of a rotation matrix (Shepperd's method, stable branch)."""
    tr = np.trace(r)
    if tr > 0:
        s = 2.0 * np.sqrt(tr + 1.0)
        return ((r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, 0.25 * s)
    i = int(np.argmax(np.diag(r)))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * np.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k])
    q = [0.0, 0.0, 0.0, 0.0]
    q[i] = 0.25 * s
    q[j] = (r[j, i] + r[i, j]) / s
    q[k] = (r[k, i] + r[i, k]) / s
    q[3] = (r[k, j] - r[j, k]) / s
    return tuple(q)


def so3_log(r):
    """Rotation vector (axis * angle [rad]) of a rotation matrix."""
    x, y, z, w = rot_to_quat(r)
    v = np.array([x, y, z])
    if w < 0:  # the shorter way round
        v, w = -v, -w
    n = np.linalg.norm(v)
    if n < 1e-12:
        return 2.0 * v
    return 2.0 * np.arctan2(n, w) * v / n


def rotation_angle(r):
    """Angle [rad] of a rotation matrix, robust near 0 and pi."""
    return float(np.linalg.norm(so3_log(r)))


def align_umeyama(est, ref, with_scale=False):
    """Rotation R, translation t, scale s minimising sum |s R est_i + t - ref_i|^2.

    est, ref: (N, 3) arrays of corresponding points, N >= 3 (Umeyama 1991;
    s = 1 unless with_scale).
    """
    est = np.asarray(est, dtype=float)
    ref = np.asarray(ref, dtype=float)
    if est.shape != ref.shape or est.shape[0] < 3:
        raise ValueError("need at least 3 corresponding points")
    mu_e = est.mean(axis=0)
    mu_r = ref.mean(axis=0)
    cov = (ref - mu_r).T @ (est - mu_e) / est.shape[0]
    u, sv, vt = np.linalg.svd(cov)
    d = np.eye(3)
    if np.linalg.det(u) * np.linalg.det(vt) < 0:
        d[2, 2] = -1.0
    r = u @ d @ vt
    s = 1.0
    if with_scale:
        var_e = np.mean(np.sum((est - mu_e) ** 2, axis=1))
        if var_e <= 0:
            raise ValueError("estimate has no spread: scale undefined")
        s = float(np.trace(np.diag(sv) @ d) / var_e)
    t = mu_r - s * r @ mu_e
    return r, t, s


def align_rigid(est, ref):
    """Rotation R and translation t minimising sum |R est_i + t - ref_i|^2 (SE(3))."""
    r, t, _ = align_umeyama(est, ref, with_scale=False)
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
    """RMS and median |distance| [m] of aligned points to the sphere surface."""
    return scene_geometry.map_error(points, r, t, [scene_geometry.Sphere(centre, radius)])
