#!/usr/bin/env python3
"""Checks sf-fls-evidence --count-looks on a short run (label bench).

usage: check_fls_looks.py COUNTS.bin FLS_FRAMES

The counts file holds voted, freed, above-seabed and looks arrays (tools/bench/fls_likelihood.py
has the layout). Fails unless: the looks array is there; no voxel was looked at in more frames
than the run has; some voxels were looked at; and the voxels voted from nearer than the seabed
were, most of them, looked at too (an above-seabed vote is only possible in a frame that held the
voxel nearer than the seabed; the two differ where an arc touches a voxel whose centre lies just
outside the fan: on the reference box's first 600 sequences 0.913 of them were looked at, and a
fan test with a sign or an angle wrong gives none).
"""
import array
import struct
import sys


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    blob = open(sys.argv[1], "rb").read()
    frames = int(sys.argv[2])
    if blob[:8] != b"SFFLSEV1":
        sys.exit("not an sf-fls-evidence file")
    nx, ny, nz = struct.unpack_from("<3i", blob, 8)
    n = nx * ny * nz
    if len(blob) != 52 + 4 * 2 * n:
        sys.exit(f"expected 4 arrays of {n} counts, file holds {(len(blob) - 52) / (2 * n):.2f}")
    arrays = []
    for k in range(4):
        a = array.array("H")
        a.frombytes(blob[52 + 2 * k * n:52 + 2 * (k + 1) * n])
        if sys.byteorder != "little":
            a.byteswap()
        arrays.append(a)
    _, _, above, looks = arrays
    failures = []
    if max(looks) > frames:
        failures.append(f"a voxel looked at in {max(looks)} frames, the run has {frames}")
    looked = sum(1 for v in looks if v > 0)
    if looked == 0:
        failures.append("no voxel was looked at")
    voted_above = [i for i in range(n) if above[i] > 0]
    if not voted_above:
        failures.append("no above-seabed vote at all: nothing to compare the looks with")
    else:
        with_looks = sum(1 for i in voted_above if looks[i] > 0)
        share = with_looks / len(voted_above)
        print(f"{looked} voxels looked at; {len(voted_above)} voted from nearer than the seabed, "
              f"{with_looks} of them looked at ({share:.3f})")
        if share < 0.75:
            failures.append(f"only {share:.3f} of the above-seabed-voted voxels were looked at (bar 0.75)")
    for f in failures:
        print("FAIL:", f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
