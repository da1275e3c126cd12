"""An ASL/EuRoC recording as a bag, for the offline evaluation (accuracy.py --recording).

The conversion is scripts/run_dataset.sh's (--convert-only): the same
converter (hapi_dataset's asl_to_bag), the same stereo rate rule
(--rate-divisor auto) and the same cache key, so the offline evaluation and
the main job score the same bag.
"""
import os
import subprocess

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
RUN_DATASET = os.path.join(REPO, "scripts", "run_dataset.sh")


def sourced_workspace():
    """The catkin workspace whose devel/ the environment has sourced (None without)."""
    for prefix in os.environ.get("CMAKE_PREFIX_PATH", "").split(":"):
        if os.path.basename(prefix.rstrip("/")) == "devel":
            return os.path.dirname(prefix.rstrip("/"))
    return None


def convert(folder, rate_divisor, cache, log):
    """The bag of the recording in `folder` (holding mav0/, or mav0 itself),
    converted on first use into `cache` (None: run_dataset.sh's own cache,
    <ws>/dataset_cache, shared with the main job); rate_divisor: "auto" or N."""
    env = dict(os.environ)
    if cache:
        env["HAPI_DATASET_CACHE"] = os.path.abspath(cache)
    ws = sourced_workspace()
    if ws:
        env["HAPI_WS"] = ws
    p = subprocess.run(["bash", RUN_DATASET, folder, "--convert-only", "--rate-divisor", str(rate_divisor)],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
    with open(log, "a") as f:
        f.write(f"$ {RUN_DATASET} {folder} --convert-only --rate-divisor {rate_divisor}\n{p.stdout}\n")
    lines = p.stdout.strip().splitlines()
    if p.returncode != 0 or not lines or not os.path.isfile(lines[-1]):
        raise RuntimeError(f"converting {folder} failed (see {log})")
    return lines[-1]


def name(bag):
    """The recording's name: run_dataset.sh names its bag NAME-KEY.bag."""
    return os.path.basename(bag).rsplit("-", 1)[0]
