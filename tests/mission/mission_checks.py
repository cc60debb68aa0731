#!/usr/bin/env python3
"""Multi-process and whole-pipeline checks, driven by ctest (tests/mission/CMakeLists.txt).

  mission_checks.py live    ROOT BUILD SCENARIO OUT   the live mission in a private netns
  mission_checks.py timing  ROOT BUILD SCENARIO OUT BUDGET_US
  mission_checks.py memory  ROOT BUILD SCENARIO OUT TOLERANCE_KB
  mission_checks.py survey  ROOT BUILD SCENARIO OUT offline|live   a survey mission (issue 13)
  mission_checks.py survey_memory ROOT BUILD SCENARIO OUT TOLERANCE_KB   survey RSS, 1 vs 4 times longer
Every check prints what it measured, then fails loudly if a bar is missed.
"""
import json
import os
import subprocess
import sys

import yaml


def run(cmd, **kw):
    print("+", " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True, **kw)


failures = []


def check(ok, what):
    print(("PASS " if ok else "FAIL ") + what, flush=True)
    if not ok:
        failures.append(what)


def live(root, build, scenario, out):
    env = dict(os.environ, SF_BUILD_DIR=build)
    run([f"{root}/tools/mission", scenario, out, "--no-build"], env=env, stdout=sys.stdout, stderr=subprocess.STDOUT)
    report = json.load(open(f"{out}/report.json"))
    status = report["live"]["status"]
    logged = report["variants"]["fused"]["messages"]
    gaps = status["seq_gaps"]
    check(status["nav_in"] > 0 and status["ps_in"] > 0 and status["fls_in"] > 0, "the daemon received NAV, PS and FLS")
    check(gaps == {"nav": 0, "fls": 0, "ps": 0}, f"no sequence gaps at the daemon (saw {gaps})")
    check(status["state"] == "mapping" and status["objects"] >= 1, "the object was detected and segmented")
    check(report["live"]["identical_to_offline_sim_log"] is True,
          "live map == offline map over the simulator's own log (byte for byte)")
    check(logged["seq_gaps"] == {"nav": 0, "fls": 0, "ps": 0},
          f"lcm-logger recorded every message (gaps {logged['seq_gaps']})")
    check(report["live"]["identical_to_offline_fused"] is True, "live map == offline map over the lcm-logger log")
    # The evaluation of the mission meets the accuracy bars (tests/accuracy/check_bars.py).
    bars = subprocess.run([sys.executable, f"{root}/tests/accuracy/check_bars.py", scenario, f"{out}/report.json"])
    check(bars.returncode == 0, "the mission's evaluation meets the accuracy bars of issue 4")


def survey(root, build, scenario, out, how, bars=False):
    """tools/mission on a survey scenario. Always: every object found, the maps
    in anchoring order, live == offline. With `bars`, also issue 13's accuracy
    bars (no false object, per-object fused precision and visible recall >= 0.8),
    which survey_field does not meet yet (docs/algorithm.md, "Survey mode")."""
    env = dict(os.environ, SF_BUILD_DIR=build)
    cmd = [f"{root}/tools/mission", scenario, out, "--no-build", "--survey"] + (["--offline-only"] if how == "offline" else [])
    run(cmd, env=env, stdout=sys.stdout, stderr=subprocess.STDOUT)
    report = json.load(open(f"{out}/report.json"))
    sc = yaml.safe_load(open(scenario))
    n_true = sum(1 for m in sc["scene"]["meshes"] if m.get("role") == "object")
    d = report["detection"]
    check(report.get("mode") == "survey", "report.json is a survey report")
    check(d["true"] == n_true, f"every object mesh is a true object ({d['true']} of {n_true})")
    check(d["found"] == d["true"], f"every object found ({d['found']} of {d['true']})")
    for o in report["objects"]:
        p, r = o["precision"], o["recall_visible"]
        print(f"  {o['name']}: fused precision {p}, visible recall {r} (map {o['map_id']})", flush=True)
        if bars:
            check(p is not None and p >= 0.8 and r is not None and r >= 0.8,
                  f"{o['name']}: fused precision {p} and visible recall {r} >= 0.8 (map {o['map_id']})")
    if bars:
        check(d["false"] == 0, f"no false object ({d['false']}, {d['duplicates']} of them duplicates)")
    maps = [m["map_id"] for m in report["maps"]]
    check(maps == list(range(1, len(maps) + 1)), f"map ids 1..n in anchoring order ({maps})")
    if how == "live":
        live = report["live"]
        gaps = live["status"]["seq_gaps"]
        check(gaps == {"nav": 0, "fls": 0, "ps": 0}, f"no sequence gaps at the daemon (saw {gaps})")
        check(live["identical_to_offline_sim_log"] is True,
              f"every live map == offline over the simulator's own log, byte for byte ({live['vs_sim_log']['files']})")
        check(live["identical_to_offline_fused"] is True,
              f"every live map == offline over the lcm-logger log, byte for byte ({live['vs_offline']['files']})")
        check(live["vs_offline"]["maps"] == len(maps), "as many live maps as offline")


def survey_repeated(src, dst, times, lines):
    """The survey with its lawnmower cut to its first `lines` lines, flown `times` times (no tie line)."""
    sc = yaml.safe_load(open(src))
    base = os.path.dirname(os.path.abspath(src))
    for m in sc["scene"]["meshes"]:
        m["file"] = os.path.join(base, m["file"])
    mower = dict(sc["trajectory"]["waypoints"][0])
    mower["points"] = mower["points"][:2 * lines]
    sc["trajectory"]["waypoints"] = [dict(mower) for _ in range(times)]
    yaml.safe_dump(sc, open(dst, "w"))


def survey_memory(build, scenario, out, tolerance_kb):
    rss = {}
    for times in (1, 4):
        sc = f"{out}/survey_{times}.yaml"
        survey_repeated(scenario, sc, times, 2)
        help_text = subprocess.run([f"{build}/apps/mapperd/sf-mapper", "--help"], capture_output=True, text=True).stdout
        map_dir = f"{out}/survey_{times}_maps" if "--map-dir" in help_text else None
        s = map_live(build, sc, out, f"survey_{times}", 20, map_dir)
        rss[times] = s["peak_rss_kb"]
        print(f"survey x{times}, live daemon: {s['nav_in']} NAV, {s['fls_in']} FLS, {s['ps_in']} PS, "
              f"peak RSS {rss[times]} kB")
    check(rss[1] > 0 and rss[4] > 0, "peak RSS measured")
    check(rss[4] - rss[1] <= tolerance_kb,
          f"peak RSS does not grow with survey length: x4 {rss[4]} kB vs x1 {rss[1]} kB (tolerance {tolerance_kb} kB)")


def scenario_with_passes(src, dst, passes):
    """The reference scenario with its pass list repeated `passes` times, mesh paths made absolute."""
    sc = yaml.safe_load(open(src))
    base = os.path.dirname(os.path.abspath(src))
    for m in sc["scene"]["meshes"]:
        m["file"] = os.path.join(base, m["file"])
    two = sc["trajectory"]["passes"]
    sc["trajectory"]["passes"] = [two[i % len(two)] for i in range(passes)]
    yaml.safe_dump(sc, open(dst, "w"))


def map_offline(build, scenario, out, name):
    log = f"{out}/{name}.lcmlog"
    run([f"{build}/sim/sf-sim", "--scenario", scenario, "--log", log, "--quiet"])
    status = f"{out}/{name}.json"
    run([f"{build}/apps/mapperd/sf-mapper", "--config", f"{ROOT}/scenarios/mapper.yaml", "--log", log,
         "--map-out", f"{out}/{name}.map", "--status-out", status, "--quiet"])
    os.remove(log)
    return json.load(open(status))


def timing(build, scenario, out, budget_us):
    s = map_offline(build, scenario, out, "timing")
    p99, mx = s["proc_us"]["p99"], s["proc_us"]["max"]
    print(f"per-message processing: p99 {p99:.0f} us, max {mx:.0f} us, budget {budget_us:.0f} us")
    check(s["ps_used"] > 1000 and s["fls_used"] > 300, "the run processed the scenario")
    check(p99 <= budget_us, f"p99 {p99:.0f} us within the budget {budget_us:.0f} us")


LIVE_RUN = r"""
set -e
ip link set lo up
ip route add 239.0.0.0/8 dev lo
url="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304"
if [ -n "${MAP_DIR:-}" ]; then out_args=(--map-dir "$MAP_DIR"); else out_args=(--map-out "$OUT/$NAME.map"); fi
"$BUILD/apps/mapperd/sf-mapper" --config "$ROOT/scenarios/mapper.yaml" --lcm-url "$url" \
    "${out_args[@]}" --status-out "$OUT/$NAME.json" --quiet & pid=$!
sleep 1.5
nice -n 5 "$BUILD/sim/sf-sim" --scenario "$SCENARIO" --publish --rate "$RATE" --lcm-url "$url" --threads 1 --quiet
sleep 1.5
kill -INT $pid
wait $pid
"""


def map_live(build, scenario, out, name, rate, map_dir=None):
    """The live daemon in a private network namespace, fed by sf-sim publishing (every finalised
    map into `map_dir` with sf-mapper --map-dir when given, else its one map into OUT/NAME.map)."""
    env = dict(os.environ, BUILD=build, ROOT=ROOT, OUT=out, NAME=name, SCENARIO=scenario, RATE=str(rate))
    if map_dir:
        os.makedirs(map_dir, exist_ok=True)
        env["MAP_DIR"] = map_dir
    run(["unshare", "-n", "bash", "-c", LIVE_RUN], env=env)
    return json.load(open(f"{out}/{name}.json"))


def memory(build, scenario, out, tolerance_kb):
    rss = {}
    for passes in (1, 4):
        sc = f"{out}/passes_{passes}.yaml"
        scenario_with_passes(scenario, sc, passes)
        s = map_live(build, sc, out, f"passes_{passes}", 20)
        rss[passes] = s["peak_rss_kb"]
        print(f"{passes} pass(es), live daemon: {s['nav_in']} NAV, {s['fls_in']} FLS, {s['ps_in']} PS, peak RSS {rss[passes]} kB")
    check(rss[1] > 0 and rss[4] > 0, "peak RSS measured")
    check(rss[4] - rss[1] <= tolerance_kb,
          f"peak RSS does not grow with mission length: 4 passes {rss[4]} kB vs 1 pass {rss[1]} kB "
          f"(tolerance {tolerance_kb} kB)")


if __name__ == "__main__":
    mode, ROOT, BUILD, SCENARIO, OUT = sys.argv[1:6]
    os.makedirs(OUT, exist_ok=True)
    if mode == "live":
        live(ROOT, BUILD, SCENARIO, OUT)
    elif mode == "timing":
        timing(BUILD, SCENARIO, OUT, float(sys.argv[6]))
    elif mode == "memory":
        memory(BUILD, SCENARIO, OUT, int(sys.argv[6]))
    elif mode == "survey":
        survey(ROOT, BUILD, SCENARIO, OUT, sys.argv[6], bars=len(sys.argv) > 7 and sys.argv[7] == "bars")
    elif mode == "survey_memory":
        survey_memory(BUILD, SCENARIO, OUT, int(sys.argv[6]))
    else:
        sys.exit(f"unknown mode {mode}")
    if failures:
        print(f"{len(failures)} check(s) failed", flush=True)
        sys.exit(1)
