"""Metrics of the skin's surface motion (docs/DESIGN.md "Surface motion",
docs/MOTION.md): truth over a frame interval, image velocity to on-surface
velocity, the error figures of the optical-flow study (thesis appendix A's
form: MAE and SD in px/frame and %, RMS and 95th percentile in mm/s) and the
velocity NEES."""
import numpy as np

# Frames slower than this [mm/s] are left out of the median relative error
# (a relative error of a near-zero speed says nothing).
RELATIVE_MIN_SPEED_MM_S = 5.0
# The surface motion is scored from this long after its first output with
# status OK: the first second has no map near the ray yet (no depth) or a
# depth from a handful of landmarks, and no flow fused.
SETTLE_S = 1.0


def interval_mean(t, values, t0, t1):
    """Mean of a sampled signal (t increasing, values N x d) over [t0, t1]:
    the trapezoid of its linear interpolation. None when [t0, t1] is not
    covered by the samples."""
    t = np.asarray(t, dtype=float)
    values = np.asarray(values, dtype=float).reshape(len(t), -1)
    if len(t) < 2 or t0 < t[0] or t1 > t[-1] or t1 <= t0:
        return None
    inner = (t > t0) & (t < t1)
    ts = np.concatenate([[t0], t[inner], [t1]])
    vs = np.column_stack([np.interp(ts, t, values[:, j]) for j in range(values.shape[1])])
    area = np.sum(0.5 * (vs[1:] + vs[:-1]) * np.diff(ts)[:, None], axis=0)
    return area / (t1 - t0)


def projection_jacobian(X, fx, fy):
    """d(u, v)/dX of the pinhole projection at X (camera frame, metres) [px/m]."""
    x, y, z = X
    return np.array([[fx / z, 0.0, -fx * x / z ** 2], [0.0, fy / z, -fy * y / z ** 2]])


def tangent_basis(n):
    """Two unit vectors spanning the plane normal to n."""
    n = np.asarray(n, dtype=float) / np.linalg.norm(n)
    a = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t1 = np.cross(n, a)
    t1 /= np.linalg.norm(t1)
    return np.column_stack([t1, np.cross(n, t1)])


def surface_velocity_from_image_velocity(image_velocity_px_per_frame, frame_rate, X, n, fx, fy):
    """On-surface velocity [mm/s] that moves the skin's image at the pixel by
    image_velocity [px/frame]. Exact for the definition s = Xdot - r (Xdot.n)/(r.n):
    the image velocity is J Xdot = J s, since J r = 0 (a move along the ray
    does not move the image), and s lies in the tangent plane."""
    B = tangent_basis(n)
    a = np.linalg.solve(projection_jacobian(X, fx, fy) @ B, np.asarray(image_velocity_px_per_frame) * frame_rate)
    return 1000.0 * (B @ a)


def flow_errors(est_px, true_px, true_speed_mm_s):
    """Appendix A's figures of per-frame image velocities (N x 2 px/frame):
    MAE and SD of the error's norm in px/frame and in % of the mean true
    image speed, and the median per-frame relative error over the frames
    faster than RELATIVE_MIN_SPEED_MM_S."""
    est_px, true_px = np.asarray(est_px, float), np.asarray(true_px, float)
    err = np.linalg.norm(est_px - true_px, axis=1)
    mean_true = float(np.mean(np.linalg.norm(true_px, axis=1)))
    out = {"frames": int(len(err)), "mae_px": float(np.mean(err)), "sd_px": float(np.std(err)),
           "mean_true_px": mean_true}
    out["mae_pct"] = 100.0 * out["mae_px"] / mean_true if mean_true > 0 else float("nan")
    out["sd_pct"] = 100.0 * out["sd_px"] / mean_true if mean_true > 0 else float("nan")
    fast = np.asarray(true_speed_mm_s) > RELATIVE_MIN_SPEED_MM_S
    rel = err[fast] / np.linalg.norm(true_px[fast], axis=1)
    out["median_relative_pct"] = float(100.0 * np.median(rel)) if len(rel) else float("nan")
    out["frames_faster_than_min"] = int(np.sum(fast))
    return out


def velocity_errors(est_mm_s, true_mm_s):
    """RMS and 95th percentile of the on-surface velocity error's norm [mm/s]."""
    err = np.linalg.norm(np.asarray(est_mm_s, float) - np.asarray(true_mm_s, float), axis=1)
    return {"samples": int(len(err)), "rms_mm_s": float(np.sqrt(np.mean(err ** 2))),
            "p95_mm_s": float(np.percentile(err, 95)), "mean_true_speed_mm_s": float(np.mean(
                np.linalg.norm(np.asarray(true_mm_s, float), axis=1)))}


def velocity_nees(est_mm_s, true_mm_s, cov_mm_s, normals):
    """Per-sample NEES of the on-surface velocity in its tangent plane (2 degrees
    of freedom: the velocity and its covariance are rank 2 in 3D)."""
    out = []
    for e, g, C, n in zip(np.asarray(est_mm_s, float), np.asarray(true_mm_s, float), cov_mm_s, normals):
        B = tangent_basis(n)
        d = B.T @ (e - g)
        S = B.T @ np.asarray(C, float).reshape(3, 3) @ B
        out.append(float(d @ np.linalg.solve(S, d)))
    return np.array(out)


def static_point_motion(X, n, v_c, w_c, fx, fy, frame_rate):
    """The motion, relative to the camera, of a static skin point X [m] with
    normal n (camera frame) under the camera's twist (v_c [m/s], w_c [rad/s],
    camera frame): (s [mm/s], normal velocity [mm/s], image velocity
    [px/frame]). docs/DESIGN.md "Surface motion": Xdot = -(v + w x X),
    s = Xdot - r (Xdot.n)/(r.n) with r the unit ray through X."""
    X, n = np.asarray(X, float), np.asarray(n, float)
    r = X / np.linalg.norm(X)
    xdot = -(np.asarray(v_c, float) + np.cross(w_c, X))
    s = xdot - r * (xdot @ n) / (r @ n)
    return 1000.0 * s, 1000.0 * float(xdot @ n), projection_jacobian(X, fx, fy) @ xdot / frame_rate


def truth_from_camera_motion(R_wc, p_wc, v_c, w_c, ray_c, surfaces, fx, fy, frame_rate):
    """The surface motion's truth at a pixel for a static scene, from the
    camera's true pose (R_wc, p_wc: camera in world), its twist in the camera
    frame (v_c [m/s], w_c [rad/s]) and the known surfaces (scene_geometry):
    (X [m], n, s [mm/s], normal velocity [mm/s], image velocity [px/frame]),
    all in the camera frame; None when the ray misses."""
    import scene_geometry
    r = np.asarray(ray_c, float) / np.linalg.norm(ray_c)
    h = scene_geometry.first_hit(surfaces, p_wc, R_wc @ r)
    if h is None:
        return None
    X, n = h[0] * r, R_wc.T @ h[1]
    return (X, n) + static_point_motion(X, n, v_c, w_c, fx, fy, frame_rate)


def log_so3(R):
    """The rotation vector of R (angle < pi)."""
    c = np.clip((np.trace(R) - 1.0) / 2.0, -1.0, 1.0)
    angle = np.arccos(c)
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / 2.0
    return w if angle < 1e-9 else w * angle / np.sin(angle)


def twist_from_poses(t, p, R):
    """The camera-frame twist (v, w) at each pose from central differences of
    its neighbours (one-sided at the ends): for a recording whose truth has
    poses but no twist. Exact to second order for a smooth motion."""
    t, p = np.asarray(t, float), np.asarray(p, float)
    out = np.zeros((len(t), 6))
    for i in range(len(t)):
        a, b = max(i - 1, 0), min(i + 1, len(t) - 1)
        dt = t[b] - t[a]
        out[i, :3] = R[i].T @ (p[b] - p[a]) / dt
        out[i, 3:] = log_so3(R[a].T @ R[b]) / dt
    return out
