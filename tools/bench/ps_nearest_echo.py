#!/usr/bin/env python3
"""What a PS ping's strongest bin and its nearest echo say about height: the evidence behind
detector.nearest_echo_sigmas (docs/algorithm.md, "Narrow objects lose the strongest bin to the
seabed").

Per log, over every PS ping: its strongest bin (paper 2.1, when at least --min-peak) and its
nearest bin pair standing --sigmas robust sigmas over the ping's median (libfusion's
firstEchoBin), each turned into a height above the seabed under the vehicle (NAV depth +
altitude: run it on flat or rough seabeds, not on slopes). The strongest bin goes on the fan's
centre line, as the detector puts it; the nearest echo on the fan's steepest edge (centre +
--beam-width / 2), where a level seabed returns first. Prints how many pings' strongest bin and
how many nearest echoes stand more than --rise above the seabed, and, over the pings whose nearest
echo comes before their strongest, how far it stands above the strongest (its lift: about 0 on a
seabed ping).

    tools/bench/ps_nearest_echo.py LOG... [--sigmas 4] [--beam-width 2] [--rise 0.15]

Standard library only (reads the log with tools/sfbag, which needs lcm-gen).
"""
import argparse
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)
from sfbag import lcmlog  # noqa: E402
from echo_noise_stops import level  # noqa: E402


def first_pair(values, lvl, start):
    for b in range(start, len(values) - 1):
        if values[b] > lvl and values[b + 1] > lvl:
            return b
    return -1


def pct(xs, q):
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(q * (len(xs) - 1) + 0.5))] if xs else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("logs", nargs="+")
    ap.add_argument("--sigmas", type=float, default=4.0, help="nearest echo: a bin pair this many robust sigmas up")
    ap.add_argument("--beam-width", type=float, default=2.0, help="the fan's vertical thickness, degrees")
    ap.add_argument("--min-peak", type=int, default=40, help="ps_selection.min_peak_intensity")
    ap.add_argument("--min-range", type=float, default=0.5, help="bins nearer than this (m) are skipped")
    ap.add_argument("--rise", type=float, default=0.15, help="m above the seabed that counts as risen")
    a = ap.parse_args()
    T = lcmlog.types()
    for log in a.logs:
        pings = strongest = strongest_risen = nearest_risen = 0
        lifts = []
        for nav, data in lcmlog.with_latest_nav(log, "PS"):
            if nav.altitude <= 0:
                continue
            m = T.ps_ping_t.decode(data)
            pings += 1
            px = list(m.intensity if isinstance(m.intensity, (bytes, bytearray)) else bytes(m.intensity))
            dr = (m.range_max - m.range_min) / max(1, m.num_bins - 1)
            start = max(0, int(math.ceil((a.min_range - m.range_min) / dr))) if dr > 0 else 0
            seabed = nav.position_ned[2] + nav.altitude
            e = m.tilt + m.head_angle
            z0 = nav.position_ned[2] + m.mount_xyz[2]
            peak = max(range(start, len(px)), key=lambda b: px[b]) if start < len(px) else -1
            h_peak = None
            if peak >= 0 and px[peak] >= a.min_peak:
                strongest += 1
                h_peak = seabed - (z0 + (m.range_min + peak * dr) * math.sin(e))
                strongest_risen += h_peak > a.rise
            near = first_pair(px, level(px[start:], a.sigmas), start)
            if near < 0:
                continue
            h_near = seabed - (z0 + (m.range_min + near * dr) * math.sin(e + math.radians(a.beam_width / 2)))
            nearest_risen += h_near > a.rise
            if h_peak is not None and near < peak:
                lifts.append(h_near - h_peak)
        print(log)
        print(f"  {pings} pings; strongest bin at or above {a.min_peak}: {strongest}, of which more than "
              f"{a.rise} m up: {strongest_risen}; nearest echo more than {a.rise} m up: {nearest_risen}")
        if lifts:
            print(f"  nearest echo before the strongest in {len(lifts)} pings; its lift over the strongest: "
                  f"median {pct(lifts, 0.5):.3f} m, 99th percentile {pct(lifts, 0.99):.3f} m, "
                  f"more than 0.1 m in {sum(x > 0.1 for x in lifts)}")


if __name__ == "__main__":
    main()
