#!/usr/bin/python3
"""Every ctest entry of the build carries exactly one of the labels unit,
system, reliability, sanitizer (cmake/HapiCommon.cmake, hapi_set_test_label),
so `scripts/test.sh --quick` (unit and system) misses no test by accident; and
every entry but a sanitizer one is RUN_SERIAL, so `ctest -j` in
scripts/test.sh runs only those beside each other.

    ctest_labels_test.py BUILD_DIR
"""
import json
import subprocess
import sys

LABELS = {"unit", "system", "reliability", "sanitizer"}


def main():
    out = subprocess.run(["ctest", "--show-only=json-v1"], cwd=sys.argv[1], capture_output=True, text=True,
                         check=True).stdout
    tests = json.loads(out)["tests"]
    bad = []
    for t in tests:
        labels = []
        serial = False
        for p in t.get("properties", []):
            if p["name"] == "LABELS":
                labels = p["value"]
            elif p["name"] == "RUN_SERIAL":
                serial = bool(p["value"])
        if len(labels) != 1 or labels[0] not in LABELS:
            bad.append("%s: %s" % (t["name"], labels or "no label"))
        elif labels[0] != "sanitizer" and not serial:
            bad.append("%s: %s test without RUN_SERIAL" % (t["name"], labels[0]))
    for b in bad:
        print("FAIL: " + b)
    print("%d ctest entries, %d without exactly one of %s or RUN_SERIAL" % (len(tests), len(bad), sorted(LABELS)))
    return 1 if bad or not tests else 0


if __name__ == "__main__":
    sys.exit(main())
