#!/usr/bin/env python3
"""How long the dark runs inside the FLS's seabed band are: the shadow evidence a detector could use.

Per FLS frame and beam, the band of ranges at which a flat seabed at the NAV altitude lies on the
beam's elevation arc (from the frame's own tilt, aperture and beam bearing, less --edge rows at
each end); inside it, the longest run of pixels at or below the image's noise level (median + 4
robust sigmas, as libfusion's free space uses). On object-free seabed these runs are speckle
dropouts; behind an object standing on the seabed they are its shadow. Prints, per log, the share
of beams whose longest run reaches k rows, and the longest run seen.

    tools/bench/fls_shadow_gaps.py LOG... [--every 20] [--edge 3]

Standard library only (reads the log with tools/sfbag, which needs lcm-gen). A flat seabed at the
NAV altitude is assumed, so run it on flat or rough seabeds, not on slopes (docs/algorithm.md,
"What the remaining misses are").
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

KS = [2, 3, 4, 5, 6, 8, 10, 12, 15, 20, 30]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("logs", nargs="+")
    ap.add_argument("--every", type=int, default=20, help="use every n-th FLS frame")
    ap.add_argument("--edge", type=int, default=3, help="rows left out at each end of the band")
    a = ap.parse_args()
    T = lcmlog.types()
    for log in a.logs:
        hist, frames = {}, 0
        for nav, data in lcmlog.with_latest_nav(log, "FLS"):
            altitude = nav.altitude
            if altitude <= 0:
                continue
            frames += 1
            if frames % a.every:
                continue
            m = T.fls_image_t.decode(data)
            px = m.data if isinstance(m.data, (bytes, bytearray)) else bytes(m.data)
            rows, cols = m.num_ranges, m.num_beams
            noise = level(list(px[::7]), 4)
            near_first = list(m.row_range)[::-1]
            r_min, r_max = near_first[0], near_first[-1]
            for c in range(cols):
                b = m.beam_bearing[c]
                # sine of the depression of the aperture's two edge rays, sensor tilted down by m.tilt
                down = [math.sin(m.tilt) * math.cos(e) * math.cos(b) + math.cos(m.tilt) * math.sin(e)
                        for e in (m.elevation_min, m.elevation_max)]
                if min(down) <= 0:
                    continue  # an edge ray at or above the horizon: no far end of the band
                near, far = altitude / max(down), altitude / min(down)
                i0 = int((near - r_min) / (r_max - r_min) * (rows - 1)) + a.edge
                i1 = int((far - r_min) / (r_max - r_min) * (rows - 1)) - a.edge
                longest = run = 0
                for i in range(max(0, i0), min(rows, i1)):
                    run = run + 1 if px[(rows - 1 - i) * cols + c] <= noise else 0
                    longest = max(longest, run)
                if i1 > i0:
                    hist[longest] = hist.get(longest, 0) + 1
        total = sum(hist.values())
        print(log)
        if not total:
            print("  no FLS beam with a seabed band")
            continue
        print(f"  {total} beams; share whose longest dark run inside the seabed band reaches k rows: " +
              ", ".join(f"{k}: {sum(v for g, v in hist.items() if g >= k) / total:.4f}" for k in KS) +
              f"; longest {max(hist)} rows")


if __name__ == "__main__":
    main()
