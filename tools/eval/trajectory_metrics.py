"""Trajectory metrics of one run against its ground truth (pure numpy, no ROS).

docs/DESIGN.md "Evaluation metrics" states the definitions:
  * ATE after an SE(3) alignment (the figure: stereo is metric) and after a
    Sim(3) alignment (reported next to it with its scale factor);
  * rotation error after the SE(3) alignment, per pose [deg];
  * RPE over a fixed time span (1 s): translation [m] and rotation [deg];
  * NEES of position and of rotation (3 dof each) with the pose covariance of
    the estimate (nav_msgs/Odometry convention: 6x6, x y z then rotation about
    the fixed axes of the header frame), and the 95 % chi-square bounds;
  * velocity error: the estimate's and the truth's twist are both in their
    child frame (the left camera), which no world alignment changes.
Poses: stamps (N,) [s], positions (N, 3), rotations (N, 3, 3) camera -> world.
"""
import numpy as np

from evaluation import align_umeyama, quat_to_rot, rotation_angle, so3_log

# 95 % two-sided chi-square bounds for 3 degrees of freedom.
CHI2_3DOF_95 = (0.2158, 9.3484)
Z_975 = 1.959963984540054


def rotations_from_quats(quats):
    return np.array([quat_to_rot(q) for q in np.asarray(quats, dtype=float).reshape(-1, 4)])


def interpolate_poses(ref_stamps, ref_p, ref_r, stamps, max_gap):
    """Reference poses at `stamps` (linear position, geodesic rotation), for
    stamps inside the reference's span whose neighbours are at most max_gap
    apart. Returns (indices of `stamps` served, positions, rotations)."""
    ref_stamps = np.asarray(ref_stamps, dtype=float)
    idx, ps, rs = [], [], []
    for i, t in enumerate(np.asarray(stamps, dtype=float)):
        k = np.searchsorted(ref_stamps, t)
        if k == 0 or k == len(ref_stamps):
            if len(ref_stamps) and abs(ref_stamps[min(k, len(ref_stamps) - 1)] - t) < 1e-9:
                j = min(k, len(ref_stamps) - 1)
                idx.append(i), ps.append(ref_p[j]), rs.append(ref_r[j])
            continue
        t0, t1 = ref_stamps[k - 1], ref_stamps[k]
        if t1 - t0 > max_gap:
            continue
        a = (t - t0) / (t1 - t0)
        d = so3_log(ref_r[k - 1].T @ ref_r[k])
        idx.append(i)
        ps.append((1 - a) * ref_p[k - 1] + a * ref_p[k])
        rs.append(ref_r[k - 1] @ exp_so3(a * d))
    return np.array(idx, dtype=int), np.array(ps).reshape(-1, 3), np.array(rs).reshape(-1, 3, 3)


def exp_so3(v):
    th = np.linalg.norm(v)
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    if th < 1e-12:
        return np.eye(3) + k
    k /= th
    return np.eye(3) + np.sin(th) * k + (1 - np.cos(th)) * k @ k


def ate(est_p, ref_p, with_scale=False):
    """ATE after alignment: dict rmse, mean, median, max, errors (N,), R, t, s."""
    r, t, s = align_umeyama(est_p, ref_p, with_scale)
    aligned = s * (r @ np.asarray(est_p, dtype=float).T).T + t
    err = np.linalg.norm(aligned - ref_p, axis=1)
    return {"rmse": float(np.sqrt(np.mean(err ** 2))), "mean": float(err.mean()),
            "median": float(np.median(err)), "max": float(err.max()), "errors": err,
            "R": r, "t": t, "s": s, "aligned": aligned}


def rotation_errors_deg(est_r, ref_r, r_align):
    """Angle [deg] of R_ref^T (R_align R_est) per pose."""
    return np.degrees([rotation_angle(g.T @ (r_align @ e)) for e, g in zip(est_r, ref_r)])


def rpe(stamps, est_p, est_r, ref_p, ref_r, delta=1.0, tol=0.03):
    """Relative pose error over `delta` seconds: (translation [m], rotation [deg]) arrays.

    For each pose i the pair (i, j) with t_j nearest to t_i + delta (within
    tol * delta); the error is the difference of the relative motions,
    E = (T_ref_i^-1 T_ref_j)^-1 (T_est_i^-1 T_est_j). Invariant to the world
    alignment.
    """
    stamps = np.asarray(stamps, dtype=float)
    trans, rot = [], []
    for i, t in enumerate(stamps):
        j = int(np.searchsorted(stamps, t + delta))
        cands = [c for c in (j - 1, j) if i < c < len(stamps)]
        if not cands:
            continue
        j = min(cands, key=lambda c: abs(stamps[c] - t - delta))
        if abs(stamps[j] - t - delta) > tol * delta:
            continue
        dr_e = est_r[i].T @ est_r[j]
        dp_e = est_r[i].T @ (est_p[j] - est_p[i])
        dr_g = ref_r[i].T @ ref_r[j]
        dp_g = ref_r[i].T @ (ref_p[j] - ref_p[i])
        trans.append(np.linalg.norm(dr_g.T @ (dp_e - dp_g)))
        rot.append(np.degrees(rotation_angle(dr_g.T @ dr_e)))
    return np.array(trans), np.array(rot)


def chi2_bounds_of_mean(dof, n, p=0.95):
    """Two-sided bounds of the mean of n chi-square(dof) samples (Wilson-Hilferty)."""
    k = dof * n
    z = Z_975 if abs(p - 0.95) < 1e-12 else None
    if z is None:
        raise ValueError("only 95 % bounds are tabulated")
    c = 2.0 / (9.0 * k)
    return tuple(k * (1 - c + sgn * z * np.sqrt(c)) ** 3 / n for sgn in (-1.0, 1.0))


def nees(errors, covariances):
    """e_i^T C_i^-1 e_i for (N, 3) errors and (N, 3, 3) covariances (NaN where C is singular)."""
    out = np.full(len(errors), np.nan)
    for i, (e, c) in enumerate(zip(errors, covariances)):
        try:
            out[i] = float(e @ np.linalg.solve(c, e))
        except np.linalg.LinAlgError:
            pass
    return out


def pose_nees(aligned_p, ref_p, est_r, ref_r, r_align, cov6):
    """Position and rotation NEES per pose after the SE(3) alignment.

    Position error in the truth's world frame, (R p_est + t) - p_ref, with the
    covariance rotated by the alignment; rotation error
    Log(R_align R_est R_ref^T), a perturbation about the world axes as the
    odometry covariance states it.
    """
    cov6 = np.asarray(cov6, dtype=float)
    e_p = np.asarray(aligned_p) - np.asarray(ref_p)
    e_r = np.array([so3_log(r_align @ e @ g.T) for e, g in zip(est_r, ref_r)])
    c_p = np.einsum("ij,njk,lk->nil", r_align, cov6[:, :3, :3], r_align)
    c_r = np.einsum("ij,njk,lk->nil", r_align, cov6[:, 3:, 3:], r_align)
    return nees(e_p, c_p), nees(e_r, c_r)


def anchor_transform(anchor):
    """(R, t) that carries the estimate's world into the truth's with the two
    tied at `anchor` (est_p0, est_r0, ref_p0, ref_r0)."""
    est_p0, est_r0, ref_p0, ref_r0 = anchor
    r_a = ref_r0 @ est_r0.T
    return r_a, ref_p0 - r_a @ est_p0


def anchored_errors(est_p, est_r, ref_p, ref_r, anchor):
    """(position errors (N, 3) [m], rotation errors (N, 3) [rad, world axes],
    r_a) with the estimate's frame tied to the truth's at `anchor` (est_p0,
    est_r0, ref_p0, ref_r0): the error of each pose once the estimate and the
    truth agree at that instant. r_a turns the estimate's world into the
    truth's."""
    r_a, t_a = anchor_transform(anchor)
    p = (r_a @ np.asarray(est_p).T).T + t_a
    r = np.einsum("ij,njk->nik", r_a, est_r)
    e_p = np.asarray(ref_p) - p
    e_r = np.array([so3_log(g @ e.T) for e, g in zip(r, ref_r)])
    return e_p, e_r, r_a


def anchored_pose_nees(est_p, est_r, ref_p, ref_r, cov6, anchor):
    """Position and rotation NEES per pose with the estimate's frame tied to the
    truth's at the instant that defines the filter's world (its reset or
    gravity alignment), where its covariance starts from its initial sigmas;
    a least-squares alignment over the whole run would also remove the drift
    the covariance accounts for.

    est_r, ref_r: (N, 3, 3); cov6: (N, 6, 6) over [position, rotation about
    the world axes] as the odometry message states it; anchor: (est_p0,
    est_r0, ref_p0, ref_r0), the estimate and the truth at that instant.
    """
    e_p, e_r, r_a = anchored_errors(est_p, est_r, ref_p, ref_r, anchor)
    cov6 = np.asarray(cov6, dtype=float)
    c_p = np.einsum("ij,njk,lk->nil", r_a, cov6[:, :3, :3], r_a)
    c_r = np.einsum("ij,njk,lk->nil", r_a, cov6[:, 3:, 3:], r_a)
    return nees(e_p, c_p), nees(e_r, c_r)


def nees_summary(values, dof=3):
    """Mean, the 95 % bounds of that mean, and the fraction of samples in the per-sample band."""
    v = values[np.isfinite(values)]
    if len(v) == 0:
        return None
    lo, hi = chi2_bounds_of_mean(dof, len(v))
    inside = np.mean((v >= CHI2_3DOF_95[0]) & (v <= CHI2_3DOF_95[1]))
    above = np.mean(v > CHI2_3DOF_95[1])
    return {"mean": float(v.mean()), "mean_bounds_95": [float(lo), float(hi)],
            "fraction_in_95_band": float(inside), "fraction_above_95_band": float(above), "samples": int(len(v))}


def velocity_errors(est_twist, ref_twist):
    """RMS of angular [rad/s] and linear [m/s] velocity differences; (N, 6) twists (linear, angular)."""
    d = np.asarray(est_twist, dtype=float) - np.asarray(ref_twist, dtype=float)
    return (float(np.sqrt(np.mean(np.sum(d[:, 3:] ** 2, axis=1)))),
            float(np.sqrt(np.mean(np.sum(d[:, :3] ** 2, axis=1)))))
