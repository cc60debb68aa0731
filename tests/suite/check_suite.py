#!/usr/bin/env python3
"""Asserts the bars of issue 9 on one suite scenario's outputs (written by run_scenario.py).

usage: check_suite.py SCENARIO.yaml OUTDIR EXPECTATIONS.yaml

With objects (expected count n >= 1), on the fused variant:
  - detected: the fused map's segmented object count >= n;
  - precision >= 0.85 and visible recall >= 0.85;
  - F1 = 2PR/(P+R) >= max(F1 of fls_only, F1 of carve_only) (no predicted voxel: P undefined, F1 = 0).
  When the fused mapper opened more than one map (OUTDIR/survey.json, sf-eval's survey scoring of
  all of them), detection is every true object found in some map, and precision and visible recall
  are each true object's own, in the map of its match; the F1 bar stays on the first maps, the only
  ones all four variants have.
Object-free (n == 0): sf-eval must have scored the maps and the fused map must report no object;
  when sf-eval could not score the run, the fused mapper's own final object count is shown (and
  judged) instead, and the missing report is a failure of its own.
Every bar is printed as `ok` or `FAIL`; the result also goes to OUTDIR/check.json for suite_table.py.
The expected count comes from report.json's `objects_true` when sf-eval writes it, else from
EXPECTATIONS; both are checked against the scenario's number of `role: object` meshes.
"""
import json
import math
import os
import re
import sys

MIN_PRECISION = 0.85
MIN_RECALL_VISIBLE = 0.85
VARIANTS = ("fls_only", "carve_only", "paper", "fused")


def load_expectations(path):
    out = {}
    with open(path) as f:
        for n, line in enumerate(f, 1):
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            m = re.fullmatch(r"([A-Za-z0-9_.-]+)\s*:\s*(\d+)", line)
            if not m:
                raise ValueError(f"{path}:{n}: expected `name: count`, got {line!r}")
            out[m.group(1)] = int(m.group(2))
    return out


def object_meshes_in(scenario_path):
    with open(scenario_path) as f:
        return len(re.findall(r"role\s*:\s*object\b", f.read()))


def f1(p, r):
    if p is None or r is None or p + r <= 0:
        return 0.0
    return 2 * p * r / (p + r)


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f), None
    except FileNotFoundError:
        return None, f"{os.path.basename(path)} missing"
    except (OSError, ValueError) as e:
        return None, f"{os.path.basename(path)} unreadable: {e}"


def objects_true_in(report):
    """sf-eval's own count of true objects, wherever it puts it (top level or per variant)."""
    if not report:
        return None
    if isinstance(report.get("objects_true"), int):
        return report["objects_true"]
    for v in report.get("variants", {}).values():
        for holder in (v, v.get("counts", {})):
            if isinstance(holder.get("objects_true"), int):
                return holder["objects_true"]
    return None


def objects_found(metrics):
    if not metrics:
        return None
    counts = metrics.get("counts", {})
    for holder in (counts, metrics):
        for key in ("objects", "objects_found", "objects_reported"):
            if isinstance(holder.get(key), int):
                return holder[key]
    return None


def check(scenario_path, out_dir, expectations_path):
    name = os.path.splitext(os.path.basename(scenario_path))[0]
    failures, lines = [], []

    def bar(ok, text):
        lines.append(("ok    " if ok else "FAIL  ") + text)
        if not ok:
            failures.append(text)

    steps, err = read_json(os.path.join(out_dir, "steps.json"))
    for s in (steps or {}).get("steps", []):
        bar(s["rc"] == 0, f"step {s['name']}: exit {s['rc']} in {s['seconds']:.1f} s"
            + (f": {s['message']}" if s["rc"] != 0 and s.get("message") else ""))
    if err:
        bar(False, f"run record {err}")

    expectations = load_expectations(expectations_path)
    meshes = object_meshes_in(scenario_path)
    report, report_err = read_json(os.path.join(out_dir, "report.json"))
    survey = None
    if os.path.exists(os.path.join(out_dir, "survey.json")):
        survey, survey_err = read_json(os.path.join(out_dir, "survey.json"))
        if survey is None or survey.get("mode") != "survey":
            bar(False, f"survey scoring of the fused maps: {survey_err or 'survey.json is not a survey report'}")
            survey = None
    from_eval = objects_true_in(report)
    if name not in expectations and from_eval is None:
        bar(False, f"no expected object count for {name} in {expectations_path}")
        expected = meshes
    else:
        expected = from_eval if from_eval is not None else expectations[name]
        if name in expectations and from_eval is not None:
            bar(from_eval == expectations[name],
                f"sf-eval's objects_true {from_eval} vs {expectations_path}: {expectations[name]}")
    bar(expected == meshes, f"expected objects {expected} vs the scenario's object meshes {meshes}")

    variants = (report or {}).get("variants", {})
    mapper_objects = {}
    fused_state = None
    for v in VARIANTS:
        st, _ = read_json(os.path.join(out_dir, f"{v}.status.json"))
        if st is not None:
            mapper_objects[v] = st.get("objects")
            if v == "fused":
                fused_state = st.get("state")
    result = {"scenario": name, "objects_true": expected, "variants": {}, "mapper_objects": mapper_objects,
              "report_error": report_err}
    for v in VARIANTS:
        m = variants.get(v)
        if m:
            p, r = m.get("precision"), m.get("recall_visible")
            result["variants"][v] = {"precision": p, "recall_visible": r, "f1": f1(p, r),
                                     "chamfer_cm": m.get("chamfer_cm"), "objects": objects_found(m)}

    if expected == 0:
        fused = result["variants"].get("fused")
        eval_failed = any(s["name"] == "sf-eval" and s["rc"] != 0 for s in (steps or {}).get("steps", []))
        if not eval_failed:  # a failed sf-eval step is already a failure above
            bar(report is not None and fused is not None,
                "sf-eval scored the object-free run" + ("" if report is not None else f" ({report_err})"))
        found = fused["objects"] if fused and fused["objects"] is not None else mapper_objects.get("fused")
        source = "report.json" if fused and fused["objects"] is not None else "sf-mapper's final status"
        bar(found == 0, f"no false object on object-free seabed: fused reports {found} (from {source}; bar 0)")
        # Issue 9: detection (paper 2.1) must never fire on seabed, even when
        # segmentation then finds nothing in the map it anchored.
        bar(fused_state == "idle", f"no detection on object-free seabed: the fused mapper ended '{fused_state}' (bar: idle, never anchored)")
    else:
        if report is None:
            bar(False, f"no sf-eval report ({report_err}): nothing to judge")
        else:
            fused = result["variants"].get("fused")
            if fused is None:
                bar(False, "report.json has no fused variant")
            elif survey is not None:
                judge_survey(survey, expected, bar, result)
            else:
                found = fused["objects"]
                bar(found is not None and found >= expected, f"detected: fused objects {found} (bar >= {expected} true)")
                p, r = fused["precision"], fused["recall_visible"]
                bar(p is not None and p >= MIN_PRECISION, f"fused precision {fmt(p)} (bar {MIN_PRECISION})")
                bar(r is not None and r >= MIN_RECALL_VISIBLE, f"fused recall_visible {fmt(r)} (bar {MIN_RECALL_VISIBLE})")
            if fused is not None:
                alone = {v: result["variants"][v]["f1"] for v in ("fls_only", "carve_only") if v in result["variants"]}
                where = " on the first maps" if survey is not None else ""
                if len(alone) < 2:
                    bar(False, "report.json lacks fls_only or carve_only: F1 bar not checked")
                else:
                    best = max(alone, key=alone.get)
                    bar(fused["f1"] + 1e-12 >= alone[best],
                        f"fused F1 {fused['f1']:.3f}{where} (bar >= max(fls_only {alone['fls_only']:.3f}, "
                        f"carve_only {alone['carve_only']:.3f}))")
    result["failures"] = failures
    result["passed"] = not failures
    with open(os.path.join(out_dir, "check.json"), "w") as f:
        json.dump(result, f, indent=2)
    print(f"suite scenario {name}:")
    print("\n".join(lines), flush=True)
    if failures:
        print(f"{name}: {len(failures)} bar(s) missed", file=sys.stderr)
        return 1
    return 0


def judge_survey(survey, expected, bar, result):
    """Detection and per-object bars over every map the fused mapper opened (sf-eval --map-dir)."""
    det = survey.get("detection", {})
    objects = survey.get("objects", [])
    bar(det.get("true") == expected, f"survey scoring's true objects {det.get('true')} vs expected {expected}")
    bar(det.get("found") == det.get("true"),
        f"detected over {det.get('maps')} maps (survey scoring): found {det.get('found')} of {det.get('true')} "
        f"true objects ({det.get('false')} false, {det.get('duplicates')} of them duplicates)")
    for o in objects:
        if not o.get("found"):
            continue
        p, r = o.get("precision"), o.get("recall_visible")
        where = f"{o.get('name')} (map {o.get('map_id')})"
        bar(p is not None and p >= MIN_PRECISION, f"fused precision of {where} {fmt(p)} (bar {MIN_PRECISION})")
        bar(r is not None and r >= MIN_RECALL_VISIBLE,
            f"fused recall_visible of {where} {fmt(r)} (bar {MIN_RECALL_VISIBLE})")
    result["survey"] = {"detection": det, "objects": [
        {k: o.get(k) for k in ("name", "found", "map_id", "precision", "recall_visible", "chamfer_cm")}
        for o in objects]}


def fmt(x):
    return "null" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.3f}"


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    sys.exit(check(*sys.argv[1:]))
