#!/usr/bin/env python3
"""The diagnosis tools score the set sf-eval scores (docs/evaluation.md, "Which rule put each voxel
in the map").

usage: check_voxel_truth.py OUTDIR SF_SIM SF_MAPPER SF_EVAL SF_MAP_VOXELS

On the 90 deg reference box, end to end through tests/suite/run_scenario.py (the four variants):
  - `sf-map-voxels` of the fused map, scored by tools/bench/voxel_truth.py against sf-eval's
    gt_object.ply, gives sf-eval's own predicted and correct voxel counts (--expect-report);
  - the same for the fls_only map, whose false slope makes the truth test count false voxels;
  - its join classes are those Segmenter::joinClass documents (1..8) and every object voxel has one;
  - `tools/resegment` on that run with the same config reproduces the run's fused precision, recall
    and F1, and with `fill_below_objects: false` it reports fewer fused voxels (the rule acts on
    saved maps: the A/B it exists for).
"""
import json
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.join(ROOT, "tools", "bench"))
import voxel_truth  # noqa: E402  (the one reader of sf-map-voxels tables)


def run(cmd, **kw):
    print("+", " ".join(cmd), flush=True)
    return subprocess.run(cmd, check=True, **kw)


def main(argv):
    if len(argv) != 5:
        sys.exit(__doc__)
    out, sim, mapper, evaluator, voxels_tool = argv
    build = os.path.dirname(os.path.dirname(os.path.dirname(evaluator)))  # BUILD/apps/eval/sf-eval
    shutil.rmtree(out, ignore_errors=True)
    runs = os.path.join(out, "runs")
    scenario = os.path.join(ROOT, "scenarios", "slope_box_90.yaml")
    config = os.path.join(ROOT, "scenarios", "mapper.yaml")
    run_dir = os.path.join(runs, "slope_box_90")
    # run_scenario.py exits 1 when a bar fails; the reference box meets them, and this test is
    # about the tools, so only its outputs matter here.
    subprocess.run([sys.executable, os.path.join(ROOT, "tests", "suite", "run_scenario.py"), scenario, config, run_dir,
                    sim, mapper, evaluator, os.path.join(ROOT, "tests", "suite", "expectations.yaml")], check=False)
    fused = os.path.join(run_dir, "fused.map")
    if not os.path.exists(fused):
        sys.exit(f"FAIL: no fused map in {run_dir}")
    figures = os.path.join(out, "figures")
    report = os.path.join(out, "report.json")
    run([evaluator, "--scenario", scenario, "--config", config, "--map", f"fused={fused}", "--json", report,
         "--figures", figures], stdout=subprocess.DEVNULL)
    table = os.path.join(out, "voxels.txt")
    run([voxels_tool, "--map", fused, "--config", config, "--out", table])
    truth = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "bench", "voxel_truth.py"), table,
                            os.path.join(figures, "gt_object.ply"), "--visible", os.path.join(figures, "gt_visible.ply"),
                            "--expect-report", report], capture_output=True, text=True)
    print(truth.stdout, truth.stderr, end="")
    failures = []
    if truth.returncode != 0:
        failures.append("voxel_truth.py's counts differ from sf-eval's report")
    # The FLS alone draws the false slope: there the truth test itself is exercised.
    fls_table = os.path.join(out, "fls_only_voxels.txt")
    run([voxels_tool, "--map", os.path.join(run_dir, "fls_only.map"), "--config", config, "--track-deg", "0",
         "--out", fls_table])  # the scenario's passes: headings 0 and 180 deg
    fls = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "bench", "voxel_truth.py"), fls_table,
                          os.path.join(figures, "gt_object.ply"), "--expect-report", os.path.join(run_dir, "report.json"),
                          "--variant", "fls_only"], capture_output=True, text=True)
    print(fls.stdout, fls.stderr, end="")
    if fls.returncode != 0:
        failures.append("voxel_truth.py's fls_only counts differ from sf-eval's report")
    with open(os.path.join(run_dir, "report.json")) as f:
        fls_counts = json.load(f)["variants"]["fls_only"]["counts"]
    if not fls_counts["predicted_correct_voxels"] < fls_counts["predicted_voxels"]:
        failures.append("fls_only scored no false voxel: the false slope is gone, so the truth test is not exercised")
    classes = {}
    for _, cls, _, object_id in voxel_truth.read_voxels(table)[1]:
        if object_id > 0:
            classes[cls] = classes.get(cls, 0) + 1
    print("object voxels per join class:", dict(sorted(classes.items())))
    if not classes or any(c < 1 or c > 8 for c in classes):
        failures.append(f"join classes outside 1..8 or no object voxel: {classes}")
    with open(report) as f:
        predicted = json.load(f)["variants"]["fused"]["counts"]["predicted_voxels"]
    if sum(classes.values()) != predicted:
        failures.append(f"sf-map-voxels lists {sum(classes.values())} object voxels, sf-eval scored {predicted}")

    # tools/resegment: the same config reproduces the run; a segmentation switch changes it.
    same = os.path.join(out, "same")
    run([os.path.join(ROOT, "tools", "resegment"), runs, same, "--config", config, "--scenarios",
         os.path.join(ROOT, "scenarios"), "--only", "slope_box_90", "--build", build], stdout=subprocess.DEVNULL)
    with open(os.path.join(run_dir, "report.json")) as f:
        before = json.load(f)["variants"]["fused"]
    with open(os.path.join(same, "slope_box_90", "report.json")) as f:
        again = json.load(f)["variants"]["fused"]
    for key in ("precision", "recall_visible"):
        if before[key] != again[key]:
            failures.append(f"resegment with the run's own config: fused {key} {again[key]} != {before[key]}")
    no_fill = os.path.join(out, "no_fill.yaml")
    with open(config) as f, open(no_fill, "w") as g:
        text = f.read()
        if "fill_below_objects: true" not in text:
            sys.exit(f"FAIL: {config} no longer sets fill_below_objects: true (update this test)")
        g.write(text.replace("fill_below_objects: true", "fill_below_objects: false"))
    other = os.path.join(out, "no_fill")
    run([os.path.join(ROOT, "tools", "resegment"), runs, other, "--config", no_fill, "--scenarios",
         os.path.join(ROOT, "scenarios"), "--only", "slope_box_90", "--build", build, "--against", same],
        stdout=subprocess.DEVNULL)
    with open(os.path.join(other, "slope_box_90", "report.json")) as f:
        without = json.load(f)["variants"]["fused"]["counts"]["predicted_voxels"]
    print(f"fused voxels: {again['counts']['predicted_voxels']} with the fill below, {without} without")
    if not without < again["counts"]["predicted_voxels"]:
        failures.append("resegment with fill_below_objects: false did not change the fused map's object voxels")
    for f_ in failures:
        print("FAIL:", f_)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
