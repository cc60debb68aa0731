#!/usr/bin/env python3
"""Multi-process and whole-pipeline checks, driven by ctest (tests/mission/CMakeLists.txt).

  mission_checks.py live    ROOT BUILD SCENARIO OUT   the live mission in a private netns
  mission_checks.py timing  ROOT BUILD SCENARIO OUT BUDGET_US
  mission_checks.py memory  ROOT BUILD SCENARIO OUT TOLERANCE_KB
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
"$BUILD/apps/mapperd/sf-mapper" --config "$ROOT/scenarios/mapper.yaml" --lcm-url "$url" \
    --map-out "$OUT/$NAME.map" --status-out "$OUT/$NAME.json" --quiet & pid=$!
sleep 1.5
nice -n 5 "$BUILD/sim/sf-sim" --scenario "$SCENARIO" --publish --rate "$RATE" --lcm-url "$url" --threads 1 --quiet
sleep 1.5
kill -INT $pid
wait $pid
"""


def map_live(build, scenario, out, name, rate):
    """The live daemon in a private network namespace, fed by sf-sim publishing."""
    env = dict(os.environ, BUILD=build, ROOT=ROOT, OUT=out, NAME=name, SCENARIO=scenario, RATE=str(rate))
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
    else:
        sys.exit(f"unknown mode {mode}")
    if failures:
        print(f"{len(failures)} check(s) failed", flush=True)
        sys.exit(1)
