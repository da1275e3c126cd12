#!/usr/bin/env python3
"""compare_backends' loop-closure figures (docs/DESIGN.md "Comparison
metrics", docs/BACKENDS.md "Loop closure on the synthetic orbit") on its
synthetic orbit, with FastSLAM 2.0 at 10 particles (seeded: the same run
every time; the bookkeeping that decides the closure is shared by every
back end):
  * pool 1000, 2 additions per step: the pool never fills, the start area
    comes back into view after step ~350 and the frames re-observe landmarks
    created in the first 50 steps (oldest_seen_step < 50; those landmarks'
    last_seen_step after step 350);
  * pool 1000, 50 additions per step: the pool turns over every ~40 steps,
    so no frame after step 300 re-observes a landmark of the first 100 steps
    and none of the first 50 steps is left in the final map;
  * the same with full_pool_keep_observations=10 (landmark_book.hpp): the
    often-observed landmarks of the first 50 steps stay in the pool (over
    400 of them), and a frame after step 300 re-observes one.
Also: every step has a non-negative background time (settle()), and the
harness (tools/eval/compare_backends.py) gives the synthetic orbit, whose
truth is on its frames' clock, no truth offset whatever --truth-offset says.

    compare_backends_loop_closure_test.py PATH/TO/compare_backends
"""
import csv
import os
import subprocess
import sys
import tempfile

FRAMES = 400


def run(tool, out, label, additions, extra=()):
    subprocess.run([tool, "--synthetic-orbit", "--algorithm", "fastslam2", "--out", out, "--label", label,
                    "--frames", str(FRAMES), "max_landmarks=1000", "max_new_landmarks=%d" % additions,
                    "fastslam_num_particles=10"] + list(extra), check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, label + "_steps.csv")) as f:
        steps = list(csv.DictReader(f))
    with open(os.path.join(out, label + "_landmarks.csv")) as f:
        landmarks = list(csv.DictReader(f))
    return steps, landmarks


def harness_offsets():
    """The truth offsets compare_backends.py passes: (synthetic orbit, recorded stream)."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "eval"))
    import compare_backends  # noqa: E402 (the harness; no ROS import at module level)
    return compare_backends.truth_offset("synthetic-orbit", -0.003), compare_backends.truth_offset(
        "no_such_stream.txt", -0.003)


def main():
    tool = sys.argv[1]
    failures = []
    synthetic, recorded = harness_offsets()
    if synthetic != 0.0 or recorded != -0.003:
        failures.append("harness truth offsets: synthetic-orbit %r (expected 0), recorded %r (expected -0.003)"
                        % (synthetic, recorded))
    with tempfile.TemporaryDirectory() as out:
        steps, landmarks = run(tool, out, "few", 2)
        if len(steps) != FRAMES:
            failures.append("few: %d steps, expected %d" % (len(steps), FRAMES))
        if any(float(s["t_background_ms"]) < 0 for s in steps):
            failures.append("negative t_background_ms")
        late = [int(s["oldest_seen_step"]) for s in steps if int(s["step"]) >= 300]
        closing = [o for o in late if 0 <= o < 50]
        if not closing:
            failures.append("2 additions per step: no frame after step 300 re-observed a landmark of steps 0-49 "
                            "(oldest seen: %s)" % (min(late) if late else None))
        start_seen_late = [l for l in landmarks if int(l["first_step"]) < 50 and int(l["last_seen_step"]) >= 350]
        if not start_seen_late:
            failures.append("2 additions per step: no landmark of steps 0-49 was seen after step 350")
        steps, landmarks = run(tool, out, "many", 50)
        late = [int(s["oldest_seen_step"]) for s in steps if int(s["step"]) >= 300]
        if not late or min(late) < 100:
            failures.append("50 additions per step: a frame after step 300 re-observed a landmark of the first "
                            "100 steps (oldest seen: %s)" % (min(late) if late else None))
        if any(int(l["first_step"]) < 50 for l in landmarks):
            failures.append("50 additions per step: landmarks of steps 0-49 still in the final map")
        steps, landmarks = run(tool, out, "kept", 50, ["full_pool_keep_observations=10"])
        kept = sum(1 for l in landmarks if int(l["first_step"]) < 50)
        if kept < 400:
            failures.append("50 additions per step, keeping the often observed: only %d landmarks of steps 0-49 "
                            "in the final map (expected over 400)" % kept)
        late = [int(s["oldest_seen_step"]) for s in steps if int(s["step"]) >= 300]
        if not [o for o in late if 0 <= o < 50]:
            failures.append("50 additions per step, keeping the often observed: no frame after step 300 "
                            "re-observed a landmark of steps 0-49 (oldest seen: %s)" % (min(late) if late else None))
    for f in failures:
        print("FAIL: " + f)
    print("loop-closure figures: %s" % ("FAILED" if failures else "ok"))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
