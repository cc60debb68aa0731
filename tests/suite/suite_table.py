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

As a module: collect(ROOT, SCENARIOS_DIR) gives the rows and the summary line's counts as data,
render(rows, summary) the table's text (tools/resegment and tools/holdout use them, so this file
stays the one reader of the scenario outputs and the one writer of the table).
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


def scenario_names(scenarios_dir):
    """The scenarios of a folder: its *.yaml files but expectations.yaml, sorted."""
    return sorted(os.path.splitext(os.path.basename(p))[0] for p in glob.glob(os.path.join(scenarios_dir, "*.yaml"))
                  if os.path.basename(p) != "expectations.yaml")


def new_row(scenario, variant, kind, **fields):
    """One row of collect(), every field present (None or "" where there is nothing)."""
    row = dict(scenario=scenario, variant=variant, kind=kind, precision=None, recall_visible=None, f1=None,
               chamfer_cm=None, found=None, found_source=None, true=None, maps=None, bars="", passed=None)
    row.update(fields)
    return row


def collect(root, scenarios_dir=SUITE):
    """The table as data: (rows, summary), in the table's order; render() prints it.

    root: a folder of scenario outputs, or a build dir holding them in tests/suite/. One row per
    scenario and variant, each a dict with
      scenario, variant, kind: "variant" (one of VARIANTS), "survey" (the fused mapper opened
        several maps: the worst object of the survey, variant "fused, all N maps (worst object)")
        or "not_run" (no check.json; variant None, one row for the scenario);
      precision, recall_visible, f1, chamfer_cm: floats, or None where the table shows "—" (f1 is
        2PR/(P+R), 0.0 when P or R is missing; None only when the variant has no sf-eval report);
      found, found_source: the objects found and who counted them ("sf-eval", "mapper": the
        sf-mapper's own final count, no sf-eval report; None: no count, found is None);
      true: the true object count; maps: the survey's map count (survey rows, else None);
      bars: "pass", "FAIL: ...", "NOT RUN: ..." on fused and not-run rows, else "";
      passed: whether the scenario meets every bar (fused rows), else None.
    summary: passed, failed, missing (did not run), total (scenarios), runtime (s, steps.json).
    """
    if os.path.isdir(os.path.join(root, "tests", "suite")):
        root = os.path.join(root, "tests", "suite")
    names = scenario_names(scenarios_dir)
    rows = []
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
            rows.append(new_row(name, None, "not_run", bars=f"NOT RUN: {why}"))
            continue
        ok = check.get("passed", False)
        passed += ok
        failed += not ok
        n_true = check.get("objects_true")
        variants = (report or {}).get("variants", {})
        for v in VARIANTS:
            m = variants.get(v)
            mapper_objects = (check.get("mapper_objects") or {}).get(v)
            row = new_row(name, v, "variant", true=n_true)
            if m is None:
                if mapper_objects is not None:
                    row.update(found=mapper_objects, found_source="mapper")
            else:
                p, r = m.get("precision"), m.get("recall_visible")
                row.update(precision=p, recall_visible=r, f1=f1(p, r), chamfer_cm=m.get("chamfer_cm"))
                counts = m.get("counts") or {}
                if "objects" in counts:
                    row.update(found=counts["objects"], found_source="sf-eval")
            if v == "fused":
                fails = check.get("failures", [])
                row.update(bars="pass" if ok else "FAIL: " + "; ".join(fails), passed=ok)
            rows.append(row)
        survey = check.get("survey")
        if survey:
            # The fused mapper opened several maps: each true object in the map of its match, worst first.
            objs = [o for o in survey.get("objects", []) if o.get("found")]
            worst_p = min((o["precision"] for o in objs if o.get("precision") is not None), default=None)
            worst_r = min((o["recall_visible"] for o in objs if o.get("recall_visible") is not None), default=None)
            det = survey.get("detection", {})
            rows.append(new_row(name, f"fused, all {det.get('maps')} maps (worst object)", "survey",
                                precision=worst_p, recall_visible=worst_r, f1=f1(worst_p, worst_r),
                                found=det.get("found"), found_source="sf-eval", true=det.get("true"),
                                maps=det.get("maps")))
    summary = dict(passed=passed, failed=failed, missing=missing, total=len(names), runtime=runtime)
    return rows, summary


def render(rows, summary):
    """collect()'s rows and summary as the markdown table (ending in a newline)."""
    lines = ["| scenario | variant | precision | recall_visible | F1 | chamfer_cm | objects found/true | bars |",
             "|---|---|---|---|---|---|---|---|"]
    for row in rows:
        name = row["scenario"]
        if row["kind"] == "not_run":
            lines.append(f"| {name} | — | — | — | — | — | — | {row['bars']} |")
            continue
        cells = [num(row["precision"]), num(row["recall_visible"]), num(row["f1"]), num(row["chamfer_cm"], 1)]
        if row["kind"] == "survey":
            lines.append(f"| {name} | {row['variant']} | " + " | ".join(cells[:3]) + f" | — | {row['found']}/{row['true']} | |")
            continue
        found = {"sf-eval": f"{row['found']}", "mapper": f"{row['found']}*"}.get(row["found_source"], "—")
        lines.append(f"| {name} | {row['variant']} | " + " | ".join(cells) + f" | {found}/{row['true']} | {row['bars']} |")
    lines.append("")
    lines.append(f"{summary['passed']} of {summary['total']} scenarios meet every bar, {summary['failed']} miss at least "
                 f"one, {summary['missing']} did not run (scenario runtime {summary['runtime']:.0f} s in total). `*`: "
                 "no sf-eval report; the sf-mapper's own final object count. `fused, all N maps`: the fused mapper "
                 "opened several maps, scored together as a survey (`sf-eval --map-dir`).")
    return "\n".join(lines) + "\n"


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
    rows, summary = collect(argv[0], suite)
    text = render(rows, summary)
    print(text)
    if out_md:
        with open(out_md, "w") as f:
            f.write(text)
    return 1 if strict and (summary["failed"] or summary["missing"]) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
