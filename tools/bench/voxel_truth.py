#!/usr/bin/env python3
"""Which segmentation rule put the false voxels in a map.

    tools/bench/voxel_truth.py VOXELS.txt GT_OBJECT.ply [--visible GT_VISIBLE.ply] [--false-out F.txt]
                               [--expect-report REPORT.json --variant V]

VOXELS.txt: `sf-map-voxels --map MAP --config CONFIG` (the object voxels, or every voxel with
--all: only the object voxels are scored). GT_OBJECT.ply, GT_VISIBLE.ply: what `sf-eval --figures
DIR` writes (DIR/gt_object.ply, DIR/gt_visible.ply; without --no-ply).

An object voxel is true when its centre lies within one voxel of a true object voxel's centre,
sf-eval's own precision test (apps/eval/metrics.cpp: the squared distance, in voxels, at most 1).
Prints, per join class (the rule that joined the voxel, Segmenter::joinClass), the true and false
voxel counts, and the medians of the counts those rules read over each; with --visible, also how
many true visible voxels the map missed. --false-out writes the false voxels' lines. With
--expect-report, exits 1 unless the predicted and correct voxel counts equal that report's (the
check that this script and the dump score the set sf-eval scores). Standard library only.
"""
import argparse
import json
import sys

CLASSES = {0: "none", 1: "PS-confirmed seed or candidate", 2: "low candidate", 3: "FLS-only extension",
           4: "straight down (fill below)", 5: "off-swath", 6: "the seabed's own voxel",
           7: "PS-crossed but outweighed", 8: "unobserved below"}
FIELDS = ("log_odds", "ps_observed", "fls_touched", "ps_echoes", "ps_crossings", "fls_above_seabed_votes")


def read_ply_centres(path):
    """Voxel centres (NED m) of an ASCII PLY written by sf-eval."""
    pts = []
    with open(path) as f:
        if f.readline().strip() != "ply":
            sys.exit(f"{path}: not a PLY file")
        for line in f:
            if line.startswith("format") and "ascii" not in line:
                sys.exit(f"{path}: not an ASCII PLY (sf-eval writes ASCII)")
            if line.strip() == "end_header":
                break
        for line in f:
            v = line.split()
            if len(v) >= 3:
                pts.append(tuple(float(x) for x in v[:3]))
    return pts


def read_voxels(path):
    resolution, rows = None, []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                words = line.split()
                if "resolution" in words:
                    resolution = float(words[words.index("resolution") + 1])
                continue
            v = line.split()
            if len(v) != 11:
                sys.exit(f"{path}: expected 11 columns per voxel (sf-map-voxels), got {len(v)}")
            rows.append(((float(v[0]), float(v[1]), float(v[2])), int(v[3]),
                         [float(v[4])] + [int(x) for x in v[5:10]], int(v[10])))
    if resolution is None:
        sys.exit(f"{path}: no resolution in its header (not written by sf-map-voxels?)")
    return resolution, rows


# sf-eval's precision test (apps/eval/metrics.cpp): within one voxel, i.e. the voxel itself or a
# face neighbour, in the half-voxel keys of voxel_key (a voxel step is 2).
FACE_STEPS = ((0, 0, 0), (2, 0, 0), (-2, 0, 0), (0, 2, 0), (0, -2, 0), (0, 0, 2), (0, 0, -2))


def voxel_key(p, res):
    """A voxel centre as integers in half-voxel units (centres are odd): exact set membership."""
    return tuple(int(round(c / res * 2)) for c in p)


def within_one_voxel(k, keys):
    return any((k[0] + dx, k[1] + dy, k[2] + dz) in keys for dx, dy, dz in FACE_STEPS)


def median(values):
    s = sorted(values)
    return s[len(s) // 2] if s else None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("voxels")
    ap.add_argument("gt_object")
    ap.add_argument("--visible")
    ap.add_argument("--false-out")
    ap.add_argument("--expect-report")
    ap.add_argument("--variant", default="fused")
    a = ap.parse_args()

    res, rows = read_voxels(a.voxels)
    truth = {voxel_key(p, res) for p in read_ply_centres(a.gt_object)}

    objects = [r for r in rows if r[3] > 0]
    per = {}
    false_lines = []
    for p, cls, counts, _ in objects:
        ok = within_one_voxel(voxel_key(p, res), truth)
        per.setdefault(cls, {True: [], False: []})[ok].append(counts)
        if not ok:
            false_lines.append(f"{p[0]:.4f} {p[1]:.4f} {p[2]:.4f} {cls} " + " ".join(str(c) for c in counts))
    correct = sum(len(v[True]) for v in per.values())
    print(f"object voxels {len(objects)}, true {correct}, false {len(objects) - correct}"
          + (f", precision {correct / len(objects):.3f}" if objects else ""))
    print("| join class | true | false | false: median " + " / ".join(FIELDS) + " |")
    print("|---|---:|---:|---|")
    for cls in sorted(per):
        t, f = per[cls][True], per[cls][False]
        med = " / ".join("-" if not f else str(median([c[i] for c in f])) for i in range(len(FIELDS)))
        print(f"| {cls} {CLASSES.get(cls, '?')} | {len(t)} | {len(f)} | {med} |")
    if a.visible:
        visible = {voxel_key(p, res) for p in read_ply_centres(a.visible)}
        predicted = {voxel_key(p, res) for p, _, _, _ in objects}
        missed = sum(1 for k in visible if not within_one_voxel(k, predicted))
        print(f"visible true voxels {len(visible)}, missed (no object voxel within one voxel) {missed}")
    if a.false_out:
        with open(a.false_out, "w") as f:
            f.write("# x y z join_class " + " ".join(FIELDS) + "\n")
            f.write("\n".join(false_lines) + ("\n" if false_lines else ""))
    if a.expect_report:
        with open(a.expect_report) as f:
            counts = json.load(f)["variants"][a.variant]["counts"]
        want = (counts["predicted_voxels"], counts["predicted_correct_voxels"])
        if want != (len(objects), correct):
            print(f"voxel_truth: predicted/correct {len(objects)}/{correct}, sf-eval's report {want[0]}/{want[1]}",
                  file=sys.stderr)
            return 1
        print(f"matches {a.expect_report} ({a.variant}: {want[0]} predicted, {want[1]} correct)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
