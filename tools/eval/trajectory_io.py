"""Trajectory, calibration and map files of the offline evaluator (no ROS).

  * TUM: "t x y z qx qy qz qw" per line, '#' comments;
  * covariance file (written next to the live run's estimate): "t c0 .. c35",
    the 6x6 odometry pose covariance row-major;
  * ASL ground truth (state_groundtruth_estimate0/data.csv): t [ns], p_RS_R,
    q_RS (w x y z), ...: the body pose, moved to the left camera with the
    camera's T_BS (T_W_cam = T_W_B T_BS);
  * T_BS: an ASL sensor.yaml (its T_BS.data) or 16 comma-separated numbers;
  * PLY (ascii or binary): the vertex list hapi_eskf exports, hapi_surface's
    meshes (vertices with a projected value, triangle faces).
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


_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
              "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
              "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def _ply_header(f, path):
    """(format, [(element, count, [(property, dtype or ('list', count dtype, item dtype))])])."""
    if f.readline().strip() != b"ply":
        raise ValueError(f"{path}: not a PLY file")
    fmt, elements = None, []
    while True:
        line = f.readline()
        if not line:
            raise ValueError(f"{path}: PLY header not terminated")
        w = line.decode("ascii", "replace").split()
        if not w or w[0] in ("comment", "obj_info"):
            continue
        if w[0] == "end_header":
            return fmt, elements
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "element":
            elements.append((w[1], int(w[2]), []))
        elif w[0] == "property" and elements:
            if w[1] == "list":
                elements[-1][2].append((w[4], ("list", _PLY_TYPES[w[2]], _PLY_TYPES[w[3]])))
            else:
                elements[-1][2].append((w[2], _PLY_TYPES[w[1]]))
        else:
            raise ValueError(f"{path}: unexpected PLY header line {line!r}")


def _ply_binary_element(data, pos, count, props, endian):
    """({property: array}, position after the element) of one binary element."""
    if all(not isinstance(t, tuple) for _, t in props):
        dt = np.dtype([(name, endian + t) for name, t in props])
        rows = np.frombuffer(data, dtype=dt, count=count, offset=pos)
        return {name: rows[name].astype(float) for name, _ in props}, pos + count * dt.itemsize
    out = {name: [] for name, _ in props}
    for _ in range(count):  # lists (faces): row by row
        for name, t in props:
            if isinstance(t, tuple):
                n = int(np.frombuffer(data, endian + t[1], 1, pos)[0])
                pos += np.dtype(t[1]).itemsize
                out[name].append(np.frombuffer(data, endian + t[2], n, pos).astype(np.int64))
                pos += n * np.dtype(t[2]).itemsize
            else:
                out[name].append(float(np.frombuffer(data, endian + t, 1, pos)[0]))
                pos += np.dtype(t).itemsize
    return out, pos


def read_ply(path):
    """{element: {property: values}} of an ascii or binary PLY file; list
    properties (faces' vertex_indices) as lists of index arrays."""
    with open(path, "rb") as f:
        fmt, elements = _ply_header(f, path)
        data = f.read()
    result = {}
    if fmt == "ascii":
        tokens, pos = data.split(), 0
        for name, count, props in elements:
            out = {p: [] for p, _ in props}
            for _ in range(count):
                for p, t in props:
                    if isinstance(t, tuple):
                        n = int(tokens[pos])
                        out[p].append(np.array([int(x) for x in tokens[pos + 1:pos + 1 + n]]))
                        pos += 1 + n
                    else:
                        out[p].append(float(tokens[pos]))
                        pos += 1
            result[name] = out
        return result
    if fmt not in ("binary_little_endian", "binary_big_endian"):
        raise ValueError(f"{path}: unknown PLY format {fmt!r}")
    endian, pos = "<" if fmt == "binary_little_endian" else ">", 0
    for name, count, props in elements:
        result[name], pos = _ply_binary_element(data, pos, count, props, endian)
    return result


def read_ply_points(path):
    """(N, 3) vertex positions of a PLY file."""
    v = read_ply(path).get("vertex")
    if not v or any(k not in v for k in "xyz"):
        raise ValueError(f"{path}: PLY has no vertex x, y, z")
    return np.column_stack([np.asarray(v[k], dtype=float) for k in "xyz"]).reshape(-1, 3)
