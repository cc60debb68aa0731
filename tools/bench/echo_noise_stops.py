#!/usr/bin/env python3
"""How often noise alone would stop carving early, per noise multiple.

libfusion stops the FLS's free space and the PS's carving at the first sample
that could be an echo: it and the next farther one stand k robust standard
deviations (1.4826 x MAD) above the image's or ping's median
(update.fls_free_space_noise_sigmas, update.ps_carve_noise_sigmas;
docs/algorithm.md, "Carving stops at the first echo"). Run it over logs of
object-free seabed, where everything before the seabed's return is water, and
it prints, per k:

  PS:  the share of pings whose stop lies more than --ps-bins bins before the
       nearest echo group (paper 2.3's closest group with the default
       selection: tau 0.7 of the ping's peak, or min_peak_intensity 40);
  FLS: the share of beams with a vote (> 150) whose stop lies more than
       --fls-rows rows before the first vote.

Any such stop there is noise. The smallest k with none is the one to use.
With --ps-window n the PS stop also takes the first run of n bins whose mean
stands k / sqrt(n) robust sigmas above the median (update.ps_carve_echo_window_voxels;
docs/algorithm.md, "Weak echoes at the fan's edge"): the share it prints is
then the price of that window on object-free seabed.

    tools/bench/echo_noise_stops.py build/tests/suite/seabed_flat_long_no_object/run.lcmlog

Standard library only (reads the log with tools/sfbag, which needs lcm-gen).
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from sfbag import lcmlog  # noqa: E402


def level(values, k):
    """Lower median + k * 1.4826 * MAD (at least 1), as libfusion computes it."""
    hist = [0] * 256
    for v in values:
        hist[v] += 1
    n = len(values)

    def lower_median(h):
        seen = 0
        for v in range(256):
            seen += h[v]
            if 2 * seen >= n:
                return v
        return 255

    med = lower_median(hist)
    dev = [0] * 256
    for v in range(256):
        dev[abs(v - med)] += hist[v]
    return med + k * 1.4826 * max(1, lower_median(dev))


def first_pair_above(seq, lvl):
    for i in range(len(seq) - 1):
        if seq[i] > lvl and seq[i + 1] > lvl:
            return i
    return None


def first_window_above(seq, lvl, med, w):
    """First of w consecutive values whose mean stands (lvl - med) / sqrt(w) above med, or of a pair above lvl."""
    need = w * med + math.sqrt(w) * (lvl - med)
    total = 0
    for i, v in enumerate(seq):
        if i + 1 < len(seq) and v > lvl and seq[i + 1] > lvl:
            return i
        if w < 2:
            continue
        total += v
        if i >= w:
            total -= seq[i - w]
        if i + 1 >= w and total > need:
            return i - w + 1
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("logs", nargs="+")
    ap.add_argument("--sigmas", default="2,2.5,3,4,6")
    ap.add_argument("--ps-bins", type=int, default=10)
    ap.add_argument("--ps-window", type=int, default=0,
                    help="also stop at the first run of this many bins whose mean stands k / sqrt(n) sigmas "
                         "above the median (update.ps_carve_echo_window_voxels: a voxel's length in bins, 5)")
    ap.add_argument("--fls-rows", type=int, default=5)
    ap.add_argument("--every", type=int, default=5, help="use every n-th ping and every 2n-th frame")
    a = ap.parse_args()
    ks = [float(k) for k in a.sigmas.split(",")]
    T = lcmlog.types()
    for log in a.logs:
        ps_n, fls_n = 0, 0
        ps_early = {k: 0 for k in ks}
        fls_early = {k: 0 for k in ks}
        n_ps = n_fls = 0
        for _, _, channel, data in lcmlog.read_events(log):
            if channel == "PS":
                n_ps += 1
                if n_ps % a.every:
                    continue
                m = T.ps_ping_t.decode(data)
                bins = list(m.intensity)
                step = (m.range_max - m.range_min) / (m.num_bins - 1)
                b0 = next((b for b in range(len(bins)) if m.range_min + b * step >= 0.3), len(bins))
                vals = bins[b0:]
                if len(vals) < 2:
                    continue
                peak = max(vals)
                if peak < 40:
                    continue
                thr = min(0.7 * peak, 40)
                group = next(i for i, v in enumerate(vals) if v > thr)
                ps_n += 1
                med = level(vals, 0.0)
                for k in ks:
                    stop = first_window_above(vals, level(vals, k), med, a.ps_window)
                    if stop is not None and stop < group - a.ps_bins:
                        ps_early[k] += 1
            elif channel == "FLS":
                n_fls += 1
                if n_fls % (2 * a.every):
                    continue
                m = T.fls_image_t.decode(data)
                px = list(m.data)
                rows, cols = m.num_ranges, m.num_beams
                levels = {k: level(px, k) for k in ks}
                for c in range(cols):
                    beam = [px[r * cols + c] for r in range(rows - 1, -1, -1)]  # nearest first
                    vote = next((i for i, v in enumerate(beam) if v > 150), None)
                    if vote is None:
                        continue
                    fls_n += 1
                    for k in ks:
                        stop = first_pair_above(beam[:vote], levels[k])
                        if stop is not None and stop < vote - a.fls_rows:
                            fls_early[k] += 1
        print(log)
        print(f"  PS  {ps_n} pings, share stopped > {a.ps_bins} bins before the group: " +
              ", ".join(f"k {k:g}: {ps_early[k] / max(ps_n, 1):.4f}" for k in ks))
        print(f"  FLS {fls_n} beams, share stopped > {a.fls_rows} rows before the first vote: " +
              ", ".join(f"k {k:g}: {fls_early[k] / max(fls_n, 1):.4f}" for k in ks))


if __name__ == "__main__":
    main()
