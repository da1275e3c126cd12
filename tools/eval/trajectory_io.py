"""Trajectory, calibration and map files of the offline evaluator (no ROS).

  * TUM: "t x y z qx qy qz qw" per line, '#' comments;
  * covariance file (written next to the live run's estimate): "t c0 .. c35",
    the 6x6 odometry pose covariance row-major;
  * ASL ground truth (state_groundtruth_estimate0/data.csv): t [ns], p_RS_R,
    q_RS (w x y z), ...: the body pose, moved to the left camera with the
    camera's T_BS (T_W_cam = T_W_B T_BS);
  * T_BS: an ASL sensor.yaml (its T_BS.data) or 16 comma-separated numbers;
  * PLY: the ascii vertex list hapi_eskf exports (x y z first).
"""
import numpy as np
import yaml

from evaluation import quat_to_rot, rot_to_quat


def _rows(path):
    rows = []
    with open(path) as f:
        for n, line in enumerate(f, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            try:
                rows.append([float(x) for x in line.replace(",", " ").split()])
            except ValueError:
                raise ValueError(f"{path}:{n}: not a row of numbers") from None
    return rows


def read_tum(path):
    rows = _rows(path)
    if not rows or any(len(r) < 8 for r in rows):
        raise ValueError(f"{path}: TUM rows need 8 numbers (t x y z qx qy qz qw)")
    a = np.array([r[:8] for r in rows])
    return {"t": a[:, 0], "p": a[:, 1:4], "q": a[:, 4:8]}


def write_tum(path, t, p, q):
    with open(path, "w") as f:
        f.write("# t x y z qx qy qz qw\n")
        for row in np.column_stack([t, p, q]):
            f.write(" ".join(f"{v:.9f}" for v in row) + "\n")


def read_covariances(path):
    rows = _rows(path)
    if any(len(r) != 37 for r in rows):
        raise ValueError(f"{path}: covariance rows need 37 numbers (t and 36 entries)")
    a = np.array(rows).reshape(-1, 37)
    return a[:, 0], a[:, 1:].reshape(-1, 6, 6)


def write_covariances(path, t, cov):
    with open(path, "w") as f:
        f.write("# t then the 6x6 pose covariance (x y z rx ry rz) row-major\n")
        for ti, c in zip(t, np.asarray(cov).reshape(-1, 36)):
            f.write(f"{ti:.9f} " + " ".join(f"{v:.9g}" for v in c) + "\n")


def read_t_bs(arg):
    """4x4 T_BS from a sensor.yaml path or 16 comma-separated numbers."""
    if arg.count(",") == 15:
        vals = [float(x) for x in arg.split(",")]
    else:
        with open(arg) as f:
            text = f.read()
        # EuRoC files open with OpenCV's "%YAML:1.0" directive, which PyYAML rejects.
        text = "\n".join(line for line in text.splitlines() if not line.startswith("%YAML"))
        vals = yaml.safe_load(text)["T_BS"]["data"]
    m = np.array(vals, dtype=float).reshape(4, 4)
    if np.abs(m[:3, :3] @ m[:3, :3].T - np.eye(3)).max() > 1e-5:
        raise ValueError("T_BS is not rigid")
    return m


def read_asl_ground_truth(path, t_bs=None):
    """ASL ground truth as a trajectory of the camera (or of the body without T_BS)."""
    rows = _rows(path)
    if not rows or any(len(r) < 8 for r in rows):
        raise ValueError(f"{path}: ASL rows need t, p (3), q (w x y z)")
    a = np.array([r[:8] for r in rows])
    t = a[:, 0] * 1e-9
    p, q = a[:, 1:4], a[:, [5, 6, 7, 4]]  # (w x y z) -> (x y z w)
    if t_bs is None:
        return {"t": t, "p": p, "q": q}
    ps, qs = [], []
    for pi, qi in zip(p, q):
        r = quat_to_rot(qi)
        ps.append(pi + r @ t_bs[:3, 3])
        qs.append(rot_to_quat(r @ t_bs[:3, :3]))
    return {"t": t, "p": np.array(ps), "q": np.array(qs)}


def read_trajectory(path, t_bs=None):
    """TUM (.txt/.tum) or ASL ground truth (.csv)."""
    if path.endswith(".csv"):
        return read_asl_ground_truth(path, t_bs)
    if t_bs is not None:
        raise ValueError("--t-bs applies to ASL ground truth (.csv) only")
    return read_tum(path)


def read_ply_points(path):
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii", "replace").strip()
            if not line:
                raise ValueError(f"{path}: PLY header not terminated")
            header.append(line)
            if line == "end_header":
                break
        if "format ascii 1.0" not in header:
            raise ValueError(f"{path}: only ascii PLY is read")
        n = next(int(h.split()[2]) for h in header if h.startswith("element vertex"))
        pts = [list(map(float, f.readline().split()[:3])) for _ in range(n)]
    return np.array(pts).reshape(-1, 3)
