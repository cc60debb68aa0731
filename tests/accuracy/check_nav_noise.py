#!/usr/bin/env python3
"""Issue 11's bar on two sf-eval reports of one reference scenario.

The noisy run (NAV with drift, heading bias and noise, position noise; the
vehicle rolling, pitching and heaving) must keep fused precision and visible
recall within 0.05 of the noise-free run. Also checks that the noisy report
measured the NAV error it was made under (sf-eval --log, NAV vs NAV_TRUTH)
and that the noise-free log carried no truth channel (nothing differs from it).
usage: check_nav_noise.py CLEAN_REPORT.json NOISY_REPORT.json
"""
import json
import sys

MAX_DROP = 0.05


def main(clean_path, noisy_path):
    clean = json.load(open(clean_path))
    noisy = json.load(open(noisy_path))
    c, n = clean["variants"]["fused"], noisy["variants"]["fused"]
    failures = []

    def bar(ok, text):
        print(("ok    " if ok else "FAIL  ") + text)
        if not ok:
            failures.append(text)

    for name, r in (("noise-free", c), ("noisy", n)):
        print(f"{name:10s} precision {r['precision']} recall_visible {r['recall_visible']} "
              f"chamfer_cm {r['chamfer_cm']} false_slope_m3 {r['false_slope_m3']} face_angle_deg {r['face_angle_deg']} "
              f"predicted_voxels {r['counts']['predicted_voxels']}")
    nav = noisy.get("navigation")
    print(f"noisy NAV error: {json.dumps(nav)}")
    for key in ("precision", "recall_visible"):
        a, b = c[key], n[key]
        bar(a is not None and b is not None and b >= a - MAX_DROP,
            f"fused {key}: noisy {b} vs noise-free {a} (bar: within {MAX_DROP})")
    bar("navigation" in clean and clean["navigation"] is None,
        "noise-free log has no NAV_TRUTH: report navigation is null")
    bar(isinstance(nav, dict) and nav["samples"] > 0 and nav["heading_rms_deg"] > 0.3 and nav["position_rms_m"] > 0.01,
        "noisy report measured the NAV error (NAV vs NAV_TRUTH)")
    if failures:
        print(f"{noisy['scenario']}: {len(failures)} bar(s) missed", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
