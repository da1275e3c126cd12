#!/usr/bin/env python3
"""surface_motion_replay end to end on generated text inputs: a still camera
over a skin plane at 0.3 m (its map snapshots), the skin sliding at a known
velocity (8 mm/s at 0.5 Hz and 4 mm/s, with a 1 mm/s tremor at 10 Hz) seen
by 40 Hz image flow with 0.02 px noise, 10 ms late. Checks the output format
(the columns of docs/DESIGN.md "Surface motion"), the statuses (no depth
before the first map snapshot, OK after), the causal on-surface velocity's
RMS error and the smoothed output's (smaller), and prints both.

  surface_motion_replay_test.py SURFACE_MOTION_REPLAY [key=value ...]

key=value settings go to the tool (a study of a setting: the error bounds
are then not checked).
"""
import math
import pathlib
import random
import subprocess
import sys
import tempfile

FX, DEPTH, RATE, ODOM_RATE, DURATION = 500.0, 0.3, 40.0, 200.0, 3.0


def skin_velocity(t):
    """[m/s] in the plane."""
    return 0.008 * math.sin(2 * math.pi * 0.5 * t) + 0.001 * math.sin(2 * math.pi * 10 * t), 0.004


def main():
    tool, settings = sys.argv[1], sys.argv[2:]
    rng = random.Random(4)
    with tempfile.TemporaryDirectory() as tmp:
        d = pathlib.Path(tmp)
        n = int(DURATION * ODOM_RATE)
        h = 1.0 / ODOM_RATE
        with open(d / "imu_rate.txt", "w") as f:
            for k in range(n + 1):
                f.write(f"{k * h:.9f} 0 0 0 0 0 0 1 0 0 0 0 0 0\n")
        with open(d / "map.txt", "w") as f:
            pts = [(0.01 * i, 0.01 * j, DEPTH + rng.gauss(0, 2e-4)) for i in range(-8, 9) for j in range(-6, 7)]
            for t in (0.5, 1.5, 2.5):  # no map before 0.5 s
                f.write(f"{t} {len(pts)} " + " ".join(f"{x:.6f} {y:.6f} {z:.6f}" for x, y, z in pts) + "\n")
        # The skin's displacement by midpoint sums on the odometry's grid.
        slide = [(0.0, 0.0)]
        for k in range(n):
            vx, vy = skin_velocity((k + 0.5) * h)
            slide.append((slide[-1][0] + h * vx, slide[-1][1] + h * vy))
        per_frame = int(ODOM_RATE / RATE)
        sigma = 0.02
        cov = [0.0] * 36
        for i in range(6):
            cov[7 * i] = sigma * sigma
        with open(d / "flow.txt", "w") as f:
            for k1 in range(per_frame, n + 1, per_frame):
                k0 = k1 - per_frame
                du = FX * (slide[k1][0] - slide[k0][0]) / DEPTH + rng.gauss(0, sigma)
                dv = FX * (slide[k1][1] - slide[k0][1]) / DEPTH + rng.gauss(0, sigma)
                row = [k0 * h, k1 * h, 319.5, 239.5, du, dv, 0, 0, 0, 0] + cov + [30, 30, 0]
                f.write(" ".join(f"{x:.9g}" for x in row) + "\n")
        subprocess.run([tool, "--odom", str(d / "imu_rate.txt"), "--map", str(d / "map.txt"), "--flow",
                        str(d / "flow.txt"), "--intrinsics", f"{FX} {FX} 319.5 239.5 640 480 {RATE}", "--flow-latency",
                        "0.01", "--out", str(d / "out.txt"), "--smoothed", str(d / "smoothed.txt")] + settings,
                       check=True)
        errors = {}
        for name in ("out.txt", "smoothed.txt"):
            rows = [list(map(float, line.split())) for line in open(d / name) if not line.startswith("#")]
            assert all(len(r) == 30 for r in rows), f"{name}: rows of 30 columns expected"
            before = [r for r in rows if r[0] < 0.5]
            after = [r for r in rows if r[0] >= 0.5]
            assert all(r[1] == 2 and math.isnan(r[8]) for r in before), f"{name}: NO_DEPTH (nan) before the map"
            assert all(r[1] == 0 for r in after), f"{name}: OK once the map is there"
            sq = []
            for r in after:
                if r[0] < 1.0:
                    continue
                vx, vy = skin_velocity(r[0])
                sq.append((r[8] - 1000 * vx) ** 2 + (r[9] - 1000 * vy) ** 2 + r[10] ** 2)
                assert abs(r[8] * r[5] + r[9] * r[6] + r[10] * r[7]) < 1e-6, "s . n == 0"
            errors[name] = math.sqrt(sum(sq) / len(sq))
        print(f"on-surface velocity RMS error: causal {errors['out.txt']:.3f} mm/s, "
              f"smoothed {errors['smoothed.txt']:.3f} mm/s")
        if not settings:
            assert errors["out.txt"] < 1.6, errors
            assert errors["smoothed.txt"] < 0.8 * errors["out.txt"], errors
    return 0


if __name__ == "__main__":
    sys.exit(main())
