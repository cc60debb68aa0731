#!/usr/bin/env python3
"""Issue 14's bar for per-ping FLS geometry, on the outputs of run_window_change.sh.

The run whose FLS range window changes mid-mission (0.83-10 m -> 0.83-7 m) must
keep fused precision and visible recall within 0.05 of the fixed-window run,
with every FLS frame the fixed run used also used (none refused for its
geometry). The changed log mapped with fls.max_geometries 1 must refuse frames
as fls_geometry_not_cached: the window really changed.
usage: check_window_change.py OUTDIR
"""
import json
import re
import sys

MAX_DROP = 0.05


def fls_used(text):
    m = re.search(r"fls (\d+)/(\d+) used", text)
    return (int(m.group(1)), int(m.group(2))) if m else None


def reason(text, name):
    m = re.search(r"^\s*" + name + r"\s+(\d+)\s*$", text, re.M)
    return int(m.group(1)) if m else 0


def main(out):
    fixed = json.load(open(f"{out}/fixed/report.json"))["variants"]["fused"]
    changed = json.load(open(f"{out}/changed/report.json"))["variants"]["fused"]
    fixed_txt = open(f"{out}/fixed/fused.mapper.txt").read()
    changed_txt = open(f"{out}/changed/fused.mapper.txt").read()
    one_txt = open(f"{out}/changed/one_geometry.mapper.txt").read()
    failures = []

    def bar(ok, text):
        print(("ok    " if ok else "FAIL  ") + text)
        if not ok:
            failures.append(text)

    for name, r in (("fixed", fixed), ("changed", changed)):
        print(f"{name:8s} precision {r['precision']} recall_visible {r['recall_visible']} chamfer_cm {r['chamfer_cm']} "
              f"false_slope_m3 {r['false_slope_m3']} predicted_voxels {r['counts']['predicted_voxels']}")
    for key in ("precision", "recall_visible"):
        a, b = fixed[key], changed[key]
        bar(a is not None and b is not None and b >= a - MAX_DROP,
            f"fused {key}: window change {b} vs fixed window {a} (bar: within {MAX_DROP})")
    uf, uc = fls_used(fixed_txt), fls_used(changed_txt)
    bar(uf is not None and uc == uf, f"FLS frames used: window change {uc} vs fixed {uf}")
    for name in ("fls_bad_geometry", "fls_geometry_mismatch", "fls_geometry_not_cached"):
        bar(reason(changed_txt, name) == 0, f"window change run: no {name} ({reason(changed_txt, name)})")
    refused = reason(one_txt, "fls_geometry_not_cached")
    bar(uc is not None and refused >= 0.4 * uc[1],
        f"fls.max_geometries 1 refuses the zoomed frames: {refused} of {uc[1] if uc else '?'} fls_geometry_not_cached")
    if failures:
        print(f"window change: {len(failures)} bar(s) missed", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1]))
