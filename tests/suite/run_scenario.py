#!/usr/bin/env python3
"""One suite scenario end to end: sf-sim -> sf-mapper (all four variants, from the one recorded
log) -> sf-eval (the mapper's config, PNG figures, no PLY) -> check_suite.py (the bars of issue 9).

sf-eval scores each variant's first map (`--map-out`). The fused mapper also writes every map it
opened (`--map-dir OUTDIR/fused_maps`); when it opened more than one (objects farther apart than a
map holds), sf-eval scores them all as a survey (`--map-dir`, OUTDIR/survey.json) and
check_suite.py judges detection and each object's precision and recall on that. With one map the
folder is removed again (its map is fused.map).

usage: run_scenario.py SCENARIO.yaml MAPPER_YAML OUTDIR SF_SIM SF_MAPPER SF_EVAL EXPECTATIONS.yaml
                       [--budget SECONDS]

Every step's exit status, time and last error line go to OUTDIR/steps.json; a step that fails or
runs out of time (the budget, default 280 s, is shared by all steps so the ctest TIMEOUT of 300 s
never cuts the record short) is a test failure with its message, and the later steps still run
on what exists, so suite_table.py has something to show. The LCM log is deleted afterwards
(SF_SUITE_KEEP_LOG=1 keeps it). Exit 0 only when every step ran and every bar holds.
"""
import glob
import json
import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, HERE)
import check_suite  # noqa: E402

VARIANTS = check_suite.VARIANTS


def last_line(path):
    try:
        with open(path, errors="replace") as f:
            lines = [l.strip() for l in f if l.strip()]
        return lines[-1][:300] if lines else ""
    except OSError:
        return ""


def eval_command(evaluator, scenario, config, maps, out, figures=True):
    """The sf-eval command scoring each variant's map: maps {variant: path} -> OUT/report.json;
    figures: also the PNG figures in OUT/figures/, no PLY (tools/resegment scores without)."""
    cmd = [evaluator, "--scenario", scenario, "--config", config]
    for v, path in maps.items():
        cmd += ["--map", f"{v}={path}"]
    cmd += ["--json", os.path.join(out, "report.json")]
    if figures:
        cmd += ["--figures", os.path.join(out, "figures"), "--no-ply"]
    return cmd


def survey_command(evaluator, scenario, config, maps_dir, out):
    """The sf-eval command scoring every map of MAPS_DIR as a survey -> OUT/survey.json."""
    return [evaluator, "--scenario", scenario, "--config", config, "--map-dir", maps_dir,
            "--json", os.path.join(out, "survey.json")]


def main(argv):
    budget = 280.0
    if "--budget" in argv:
        k = argv.index("--budget")
        budget = float(argv[k + 1])
        argv = argv[:k] + argv[k + 2:]
    if len(argv) != 7:
        sys.exit(__doc__)
    scenario, config, out, sim, mapper, evaluator, expectations = argv
    os.makedirs(out, exist_ok=True)
    maps_dir = os.path.join(out, "fused_maps")
    shutil.rmtree(maps_dir, ignore_errors=True)
    for stale in ["report.json", "survey.json", "check.json", "steps.json", "run.lcmlog"] + [f"{v}.map" for v in VARIANTS] \
            + [f"{v}.status.json" for v in VARIANTS]:
        if os.path.exists(os.path.join(out, stale)):
            os.remove(os.path.join(out, stale))
    deadline = time.monotonic() + budget
    steps = []

    def run(name, cmd, stdout_name):
        left = deadline - time.monotonic()
        log = os.path.join(out, stdout_name)
        t0 = time.monotonic()
        if left <= 1:
            rc, message = -1, "not run: the time budget was used up by earlier steps"
        else:
            with open(log, "w") as so, open(log + ".err", "w") as se:
                try:
                    rc = subprocess.run(cmd, stdout=so, stderr=se, timeout=left).returncode
                    # the last error line: stderr, else stdout (sf-mapper logs its errors there)
                    message = (last_line(log + ".err") or last_line(log)) if rc != 0 else ""
                    if rc != 0 and rc < 0:
                        message = f"killed by signal {-rc}; " + message
                except subprocess.TimeoutExpired:
                    rc, message = -1, f"timed out after {left:.0f} s (suite budget {budget:.0f} s)"
                except OSError as e:
                    rc, message = -1, f"cannot run {cmd[0]}: {e}"
        steps.append({"name": name, "rc": rc, "seconds": round(time.monotonic() - t0, 2), "message": message,
                      "log": log})
        print(f"{name}: exit {rc} in {steps[-1]['seconds']:.1f} s" + (f": {message}" if rc else ""), flush=True)
        return rc == 0

    t_start = time.monotonic()
    lcmlog = os.path.join(out, "run.lcmlog")
    if run("sf-sim", [sim, "--scenario", scenario, "--log", lcmlog, "--threads", "1", "--quiet"], "sim.txt"):
        maps = {}
        os.makedirs(maps_dir)
        for v in VARIANTS:
            m = os.path.join(out, f"{v}.map")
            every_map = ["--map-dir", maps_dir] if v == "fused" else []
            if run(f"sf-mapper {v}", [mapper, "--config", config, "--log", lcmlog, "--map-out", m, "--variant", v,
                                       "--status-out", os.path.join(out, f"{v}.status.json")] + every_map,
                   f"{v}.mapper.txt"):
                maps[v] = m
        if maps:
            run("sf-eval", eval_command(evaluator, scenario, config, maps, out), "eval.txt")
        if len(glob.glob(os.path.join(maps_dir, "map_*.map"))) > 1:
            run("sf-eval survey", survey_command(evaluator, scenario, config, maps_dir, out), "survey.txt")
        else:
            shutil.rmtree(maps_dir, ignore_errors=True)
    if os.path.exists(lcmlog) and os.environ.get("SF_SUITE_KEEP_LOG") != "1":
        os.remove(lcmlog)
    with open(os.path.join(out, "steps.json"), "w") as f:
        json.dump({"scenario": scenario, "seconds": round(time.monotonic() - t_start, 2), "steps": steps}, f, indent=2)
    return check_suite.check(scenario, out, expectations)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
