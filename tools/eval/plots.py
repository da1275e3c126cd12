"""PNG plots of one evaluation (matplotlib, Agg backend: no display needed).

write_plots(series, out_dir) draws what run_analysis.analyse() returned:
  trajectory.png       estimate (SE(3)-aligned) and truth, top (x-y) and side (x-z) views;
  error_over_time.png  position error [m] and rotation error [deg] over time (after the SE(3)
                       alignment; standing still: tied to the truth at the first pose);
  nees.png             position and rotation NEES over time with the 95 % chi-square band
                       (only when the estimate carried covariances);
  surface_velocity.png the skin's on-surface velocity at the imaging pixel, estimate and
                       truth (only when the run had a surface-motion output and its truth).
Returns the files written. matplotlib is imported here only, so that the
metrics never depend on it.
"""
import os

from trajectory_metrics import CHI2_3DOF_95

PLOT_FILES = ("trajectory.png", "error_over_time.png", "nees.png", "surface_velocity.png")


def available():
    """None when matplotlib can be used, else the reason."""
    try:
        import matplotlib  # noqa: F401
    except ImportError as e:
        return f"matplotlib missing ({e}); install python3-matplotlib"
    return None


def write_plots(series, out_dir):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if "t" not in series:
        return []
    os.makedirs(out_dir, exist_ok=True)
    written = []

    def save(fig, name):
        path = os.path.join(out_dir, name)
        fig.tight_layout()
        fig.savefig(path, dpi=100)
        plt.close(fig)
        written.append(path)

    est, gt = series["est_aligned"], series["truth"]
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.5))
    for ax, (i, j, title) in zip(axes, ((0, 1, "top view (x-y)"), (0, 2, "side view (x-z)"))):
        ax.plot(gt[:, i], gt[:, j], "k-", lw=1.5, label="ground truth")
        ax.plot(est[:, i], est[:, j], "r-", lw=1.0, label="estimate (SE(3)-aligned)")
        ax.plot(gt[0, i], gt[0, j], "go", label="start")
        ax.set_xlabel("xyz"[i] + " [m]")
        ax.set_ylabel("xyz"[j] + " [m]")
        ax.set_title(title)
        ax.axis("equal")
        ax.grid(True, alpha=0.3)
    axes[0].legend(loc="best")
    save(fig, PLOT_FILES[0])

    t = series["t"]
    fig, axes = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
    axes[0].plot(t, series["position_error_m"], "b-")
    axes[0].set_ylabel("position error [m]")
    axes[1].plot(t, series["rotation_error_deg"], "m-")
    axes[1].set_ylabel("rotation error [deg]")
    axes[1].set_xlabel("time since first matched pose [s]")
    for ax in axes:
        ax.grid(True, alpha=0.3)
    axes[0].set_title(series.get("error_title", "error after SE(3) alignment"))
    save(fig, PLOT_FILES[1])

    if "nees_position" in series or "nees_rotation" in series:
        fig, axes = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
        for ax, key, label in zip(axes, ("nees_position", "nees_rotation"), ("position", "rotation")):
            if key in series:
                ax.semilogy(t, series[key], ".", ms=2, label=f"{label} NEES (3 dof)")
            ax.axhspan(*CHI2_3DOF_95, color="g", alpha=0.15, label="95 % chi-square band")
            ax.axhline(3.0, color="g", lw=0.8)
            ax.set_ylabel("NEES")
            ax.legend(loc="upper right")
            ax.grid(True, alpha=0.3)
        axes[1].set_xlabel("time since first matched pose [s]")
        save(fig, PLOT_FILES[2])

    sm = series.get("surface_motion")
    if sm is not None:
        fig, axes = plt.subplots(3, 1, figsize=(10, 7), sharex=True)
        for j, ax in enumerate(axes):
            ax.plot(sm["t"], sm["truth"][:, j], "k-", lw=1.5, label="truth")
            ax.plot(sm["t"], sm["estimate"][:, j], "b-", lw=0.8, label="estimate")
            ax.set_ylabel("xyz"[j] + " [mm/s]")
            ax.grid(True, alpha=0.3)
        axes[0].legend(loc="upper right")
        axes[0].set_title("on-surface velocity at the imaging pixel (imaging camera frame)")
        axes[2].set_xlabel("time since the first scored output [s]")
        save(fig, PLOT_FILES[3])
    return written
