#!/usr/bin/env python3
"""Collects the suite's results and prints ONE markdown table: scenario x variant -> precision,
visible recall, F1, Chamfer, objects found / true, and the bars (fused rows).

usage: suite_table.py BUILD_DIR [--out FILE.md] [--strict] [--scenarios DIR]

Reads BUILD_DIR/tests/suite/<scenario>/{check.json,report.json,steps.json} (or BUILD_DIR itself
when it holds the scenario folders) for every scenario of scenarios/suite/. A scenario that did
not run, or whose mapper or evaluator failed, gets a row saying so; nothing here raises on a
missing or broken file. --strict: exit 1 when any scenario missed a bar or did not run (the
ctest `suite_table` uses it, so --output-on-failure shows the table whenever something failed).
--scenarios DIR: the folder whose *.yaml files name the rows (default scenarios/suite;
tools/holdout passes scenarios/holdout).
"""
import glob
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SUITE = os.path.normpath(os.path.join(HERE, "..", "..", "scenarios", "suite"))
VARIANTS = ("fls_only", "carve_only", "paper", "fused")


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def num(x, digits=3):
    return "—" if x is None else f"{x:.{digits}f}"


def f1(p, r):
    if p is None or r is None or p + r <= 0:
        return 0.0
    return 2 * p * r / (p + r)


def main(argv):
    strict = "--strict" in argv
    argv = [a for a in argv if a != "--strict"]
    out_md = None
    suite = SUITE
    if "--scenarios" in argv:
        k = argv.index("--scenarios")
        suite = argv[k + 1]
        argv = argv[:k] + argv[k + 2:]
    if "--out" in argv:
        k = argv.index("--out")
        out_md = argv[k + 1]
        argv = argv[:k] + argv[k + 2:]
    if len(argv) != 1:
        sys.exit(__doc__)
    root = argv[0]
    if os.path.isdir(os.path.join(root, "tests", "suite")):
        root = os.path.join(root, "tests", "suite")
    names = sorted(os.path.splitext(os.path.basename(p))[0] for p in glob.glob(os.path.join(suite, "*.yaml"))
                   if os.path.basename(p) != "expectations.yaml")
    rows = ["| scenario | variant | precision | recall_visible | F1 | chamfer_cm | objects found/true | bars |",
            "|---|---|---|---|---|---|---|---|"]
    passed = failed = missing = 0
    runtime = 0.0
    for name in names:
        d = os.path.join(root, name)
        check, report, steps = load(os.path.join(d, "check.json")), load(os.path.join(d, "report.json")), \
            load(os.path.join(d, "steps.json"))
        if steps:
            runtime += steps.get("seconds", 0.0)
        if check is None:
            missing += 1
            why = "not run"
            if steps:
                bad = [s for s in steps.get("steps", []) if s.get("rc") != 0]
                why = "; ".join(f"{s['name']} failed: {s.get('message', '')}" for s in bad) or "no check.json"
            rows.append(f"| {name} | — | — | — | — | — | — | NOT RUN: {why} |")
            continue
        ok = check.get("passed", False)
        passed += ok
        failed += not ok
        n_true = check.get("objects_true")
        variants = (report or {}).get("variants", {})
        for v in VARIANTS:
            m = variants.get(v)
            mapper_objects = (check.get("mapper_objects") or {}).get(v)
            if m is None:
                cells = ["—"] * 4
                found = f"{mapper_objects}*" if mapper_objects is not None else "—"
            else:
                p, r = m.get("precision"), m.get("recall_visible")
                cells = [num(p), num(r), num(f1(p, r)), num(m.get("chamfer_cm"), 1)]
                found = (m.get("counts") or {}).get("objects", "—")
            bars = ""
            if v == "fused":
                fails = check.get("failures", [])
                bars = "pass" if ok else "FAIL: " + "; ".join(fails)
            rows.append(f"| {name} | {v} | " + " | ".join(cells) + f" | {found}/{n_true} | {bars} |")
        survey = check.get("survey")
        if survey:
            # The fused mapper opened several maps: each true object in the map of its match, worst first.
            objs = [o for o in survey.get("objects", []) if o.get("found")]
            worst_p = min((o["precision"] for o in objs if o.get("precision") is not None), default=None)
            worst_r = min((o["recall_visible"] for o in objs if o.get("recall_visible") is not None), default=None)
            det = survey.get("detection", {})
            rows.append(f"| {name} | fused, all {det.get('maps')} maps (worst object) | {num(worst_p)} | {num(worst_r)} | "
                        f"{num(f1(worst_p, worst_r))} | — | {det.get('found')}/{det.get('true')} | |")
    rows.append("")
    rows.append(f"{passed} of {len(names)} scenarios meet every bar, {failed} miss at least one, {missing} did not run"
                f" (scenario runtime {runtime:.0f} s in total). `*`: no sf-eval report; the sf-mapper's own final "
                "object count. `fused, all N maps`: the fused mapper opened several maps, scored together as a survey "
                "(`sf-eval --map-dir`).")
    text = "\n".join(rows) + "\n"
    print(text)
    if out_md:
        with open(out_md, "w") as f:
            f.write(text)
    return 1 if strict and (failed or missing) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
