#!/usr/bin/env python3
"""Asserts the accuracy bars of issue 4 on an sf-eval report.json.

fused against fls_only, speckle on: at least 80 % less false-slope volume,
precision >= 0.8, recall on the visible surface >= 0.8, and where the scenario
declares an end-face angle below 90 deg (the slope box), the fitted angle within
5 deg of it. The paper variant is reported, never judged.
usage: check_bars.py SCENARIO.yaml report.json
"""
import json
import sys

MIN_FALSE_SLOPE_REDUCTION = 0.80
MIN_PRECISION = 0.8
MIN_RECALL_VISIBLE = 0.8
MAX_FACE_ANGLE_ERROR_DEG = 5.0


def main(scenario_path, report_path):
    with open(report_path) as f:
        report = json.load(f)
    variants = report["variants"]
    fused, fls_only = variants["fused"], variants["fls_only"]
    failures = []

    def bar(ok, text):
        print(("ok    " if ok else "FAIL  ") + text)
        if not ok:
            failures.append(text)

    for name in ("fls_only", "carve_only", "paper", "fused"):
        m = variants.get(name)
        if m:
            print(f"{name:10s} precision {m['precision']} recall_visible {m['recall_visible']} "
                  f"false_slope_m3 {m['false_slope_m3']} face_angle_deg {m['face_angle_deg']}")
    reduction = 1.0 - fused["false_slope_m3"] / fls_only["false_slope_m3"]
    bar(reduction >= MIN_FALSE_SLOPE_REDUCTION,
        f"false-slope volume vs fls_only: {100 * reduction:.1f} % less (bar {100 * MIN_FALSE_SLOPE_REDUCTION:.0f} %)")
    bar(fused["precision"] is not None and fused["precision"] >= MIN_PRECISION,
        f"fused precision {fused['precision']} (bar {MIN_PRECISION})")
    bar(fused["recall_visible"] >= MIN_RECALL_VISIBLE,
        f"fused recall_visible {fused['recall_visible']} (bar {MIN_RECALL_VISIBLE})")
    true_angle = fused.get("face_angle_true_deg")
    if true_angle is not None and true_angle < 89.0:
        angle = fused["face_angle_deg"]
        bar(angle is not None and abs(angle - true_angle) <= MAX_FACE_ANGLE_ERROR_DEG,
            f"fused end-face angle {angle} vs true {true_angle} (bar +-{MAX_FACE_ANGLE_ERROR_DEG})")
    if failures:
        print(f"{scenario_path}: {len(failures)} accuracy bar(s) missed", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
