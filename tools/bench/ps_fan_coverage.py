#!/usr/bin/env python3
"""Which PS pings held a point in their fan: the evaluator's PS visibility against the pings.

sf-eval counts a surface sample as seen by the PS when, at some pose, it lies inside the whole
head sector (tilt + [head_min, head_max]) and the fan's bearings (docs/evaluation.md, "Visible
surface V"): the head sweeps that sector over the run, so the test takes its union at every
pose. A ping, though, holds only its own profiling angle, the fan's vertical beam width thick.
Per point this prints both counts over every PS ping of a log: the pings whose pose held the
point inside the sector (the evaluator's test, no line of sight) and the pings whose fan, at its
own head angle +- --beam-width / 2, held it (docs/algorithm.md, "The mine 1 m off: what the PS
sector's corner holds").

    tools/bench/ps_fan_coverage.py LOG --point=X,Y,Z [--point=X,Y,Z ...] [--beam-width 2] [--head-min -20] [--head-max 20]

Points are world NED, m (write `--point=X,Y,Z`: a negative X would read as an option). The sensor pose is NAV's position and heading plus the ping's mount
offset, vehicle level (roll and pitch left out: run it on logs without vehicle motion).
Standard library only (reads the log with tools/sfbag, which needs lcm-gen).
"""
import argparse
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
from sfbag import lcmlog  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("log")
    ap.add_argument("--point", action="append", required=True, help="X,Y,Z world NED, m (repeatable)")
    ap.add_argument("--beam-width", type=float, default=2.0, help="the fan's vertical thickness, degrees")
    ap.add_argument("--head-min", type=float, default=-20.0, help="the head sector's lower end, degrees")
    ap.add_argument("--head-max", type=float, default=20.0, help="the head sector's upper end, degrees")
    a = ap.parse_args()
    try:
        pts = [tuple(float(v) for v in p.split(",")) for p in a.point]
    except ValueError:
        sys.exit("points are X,Y,Z")
    if any(len(p) != 3 for p in pts):
        sys.exit("points are X,Y,Z")
    T = lcmlog.types()
    half = math.radians(a.beam_width / 2.0)
    lo, hi = math.radians(a.head_min), math.radians(a.head_max)
    in_sector = [0] * len(pts)
    in_fan = [0] * len(pts)
    nearest = [math.inf] * len(pts)
    pings = 0
    for nav, data in lcmlog.with_latest_nav(a.log, "PS"):
        m = T.ps_ping_t.decode(data)
        pings += 1
        c, s = math.cos(nav.rpy[2]), math.sin(nav.rpy[2])
        sx = nav.position_ned[0] + c * m.mount_xyz[0] - s * m.mount_xyz[1]
        sy = nav.position_ned[1] + s * m.mount_xyz[0] + c * m.mount_xyz[1]
        sz = nav.position_ned[2] + m.mount_xyz[2]
        for k, (x, y, z) in enumerate(pts):
            dx, dy, dz = x - sx, y - sy, z - sz
            forward, lateral = c * dx + s * dy, -s * dx + c * dy
            r = math.sqrt(dx * dx + dy * dy + dz * dz)
            if r < m.range_min or r > m.range_max:
                continue
            bearing = math.atan2(lateral, forward)
            if bearing < m.fan_min or bearing > m.fan_max:
                continue
            depression = math.atan2(dz, math.hypot(forward, lateral))
            if m.tilt + lo <= depression <= m.tilt + hi:
                in_sector[k] += 1
            off = abs(depression - (m.tilt + m.head_angle))
            nearest[k] = min(nearest[k], off)
            if off <= half:
                in_fan[k] += 1
    print(f"{pings} PS pings in {a.log}")
    print("point (NED, m)              in the sector  in a ping's fan  nearest fan (deg)")
    for k, p in enumerate(pts):
        near = f"{math.degrees(nearest[k]):.2f}" if math.isfinite(nearest[k]) else "-"
        print(f"{p[0]:7.3f} {p[1]:7.3f} {p[2]:7.3f}      {in_sector[k]:13d}  {in_fan[k]:15d}  {near:>17}")


if __name__ == "__main__":
    main()
