#!/usr/bin/env python3
"""FLS returns from nearer than the seabed: the evidence an FLS-based detector would have
(docs/algorithm.md, "Narrow objects lose the strongest bin to the seabed", found while probing).

Per FLS frame: the pixels above --threshold (the vote threshold, 150) whose range is shorter
than the range at which the beam's steepest ray meets a flat seabed at the NAV altitude, less
--margin. Nothing but a surface standing above the seabed (or noise in the water) returns from
there. Prints, per log, the frames holding such pixels, the pixels, and the 0.5 m cells (world
north/east) where most of them fall, each pixel placed on its arc's centre line.

    tools/bench/fls_near_returns.py LOG... [--threshold 150] [--margin 0.15] [--cell 0.5]

Standard library only (reads the log with tools/sfbag, which needs lcm-gen). A flat seabed at the
NAV altitude is assumed: run it on flat or rough seabeds, not on slopes.
"""
import argparse
import collections
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
from sfbag import lcmlog  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("logs", nargs="+")
    ap.add_argument("--threshold", type=int, default=150, help="pixel level that votes (update.fls_intensity_threshold)")
    ap.add_argument("--margin", type=float, default=0.15, help="m taken off the seabed's nearest range")
    ap.add_argument("--cell", type=float, default=0.5, help="cell size (m) of the where-they-fall count")
    a = ap.parse_args()
    T = lcmlog.types()
    for log in a.logs:
        frames = with_near = pixels = 0
        cells = collections.Counter()
        for nav, data in lcmlog.with_latest_nav(log, "FLS"):
            if nav.altitude <= 0:
                continue
            m = T.fls_image_t.decode(data)
            frames += 1
            steepest = math.sin(m.tilt + m.elevation_max)
            if steepest <= 0:
                continue
            nearest = (nav.altitude - m.mount_xyz[2]) / steepest - a.margin
            px = m.data if isinstance(m.data, (bytes, bytearray)) else bytes(m.data)
            cols = m.num_beams
            found = 0
            for row in range(m.num_ranges):
                r = m.row_range[row]
                if r >= nearest:
                    continue
                line = px[row * cols:(row + 1) * cols]
                for c in range(cols):
                    if line[c] > a.threshold:
                        found += 1
                        h = r * math.cos(m.tilt)  # the arc's centre line, horizontally
                        yaw = nav.rpy[2] + m.mount_roll_yaw[1] + m.beam_bearing[c]
                        cells[(math.floor((nav.position_ned[0] + h * math.cos(yaw)) / a.cell),
                               math.floor((nav.position_ned[1] + h * math.sin(yaw)) / a.cell))] += 1
            if found:
                with_near += 1
                pixels += found
        print(log)
        print(f"  {frames} frames; {with_near} hold pixels above {a.threshold} nearer than the seabed "
              f"({pixels} pixels)")
        if cells:
            top = ", ".join(f"({x * a.cell:.1f}, {y * a.cell:.1f}): {n}" for (x, y), n in cells.most_common(4))
            print(f"  most of them in the {a.cell} m cells (north, east of their corner): {top}")


if __name__ == "__main__":
    main()
