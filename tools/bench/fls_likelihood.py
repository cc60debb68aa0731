#!/usr/bin/env python3
"""The FLS's inverse sensor model, measured against ground truth.

Reads the per-voxel counts of `sf-fls-evidence` and the ground truth that
`sf-eval --figures DIR` writes (DIR/gt_object.ply, DIR/gt_visible.ply) and
prints, per FLS frame in which the mapper voted or freed a voxel:

  P(freed | surface)      over the visible true surface voxels
  P(freed | voted water)  over voxels ever voted that lie more than one voxel
                          from the object and more than --seabed-clearance
                          above --seabed-depth (the FLS's false votes)

and the log-likelihood ratios of the two outcomes, ln P(o|surface)/P(o|water).
Their ratio |LLR(freed)| / LLR(voted) is how much one frame that saw a voxel as
water should outweigh one frame that voted it (docs/algorithm.md, "FLS
free-space weight").

Counts file (sf-fls-evidence --out): "SFFLSEV1", int32 nx ny nz, float64
resolution, float64 origin[3] (min corner, NED), then uint16 voted[n] and
uint16 freed[n] (with --seabed-depth, then uint16 above_seabed[n], and with
--count-looks too, uint16 looks[n]: neither is read here), n = nx*ny*nz, linear index (iz*ny + iy)*nx + ix, little-endian.
Standard library only.
"""
import argparse
import array
import math
import struct
import sys


def read_counts(path):
    with open(path, "rb") as f:
        blob = f.read()
    if blob[:8] != b"SFFLSEV1":
        sys.exit(f"{path}: not an sf-fls-evidence file")
    nx, ny, nz = struct.unpack_from("<3i", blob, 8)
    res, = struct.unpack_from("<d", blob, 20)
    origin = struct.unpack_from("<3d", blob, 28)
    n = nx * ny * nz
    voted = array.array("H"); voted.frombytes(blob[52:52 + 2 * n])
    freed = array.array("H"); freed.frombytes(blob[52 + 2 * n:52 + 4 * n])
    if sys.byteorder != "little":
        voted.byteswap(); freed.byteswap()
    return (nx, ny, nz), res, origin, voted, freed


def read_ply_points(path):
    with open(path) as f:
        text = f.read()
    body = text.split("end_header\n", 1)[1]
    return [tuple(float(v) for v in line.split()[:3]) for line in body.splitlines() if line.strip()]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("counts", help="sf-fls-evidence --out file")
    ap.add_argument("figures", help="sf-eval --figures directory of the same run")
    ap.add_argument("--seabed-depth", type=float, required=True, help="the scenario's seabed_depth, m")
    ap.add_argument("--seabed-clearance", type=float, default=0.25,
                    help="water voxels lie at least this far above the seabed depth, m (default 0.25)")
    a = ap.parse_args()

    (nx, ny, nz), res, origin, voted, freed = read_counts(a.counts)

    def index(p):
        i = [int(math.floor((p[k] - origin[k]) / res)) for k in range(3)]
        if not (0 <= i[0] < nx and 0 <= i[1] < ny and 0 <= i[2] < nz):
            return None
        return i

    near = set()
    for p in read_ply_points(f"{a.figures}/gt_object.ply"):
        i = index(p)
        if i is None:
            continue
        for dz in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dx in (-1, 0, 1):
                    near.add(((i[2] + dz) * ny + i[1] + dy) * nx + i[0] + dx)

    surf_v = surf_f = n_surf = 0
    for p in read_ply_points(f"{a.figures}/gt_visible.ply"):
        i = index(p)
        if i is None:
            continue
        lin = (i[2] * ny + i[1]) * nx + i[0]
        surf_v += voted[lin]; surf_f += freed[lin]; n_surf += 1

    water_v = water_f = n_water = 0
    top_iz = int(math.floor((a.seabed_depth - a.seabed_clearance - origin[2]) / res))  # layers above
    for iz in range(0, max(0, min(nz, top_iz))):
        base = iz * ny * nx
        for lin in range(base, base + ny * nx):
            v = voted[lin]
            if v == 0 or lin in near:
                continue
            water_v += v; water_f += freed[lin]; n_water += 1

    if surf_v + surf_f == 0 or water_v + water_f == 0:
        sys.exit("no FLS frames on the surface or on voted water: nothing to measure")
    eps = 0.5  # half a frame: a count of zero stays finite
    p_free_surf = max(surf_f, eps) / (surf_v + surf_f)
    p_free_water = max(water_f, eps) / (water_v + water_f)
    llr_free = math.log(p_free_surf / p_free_water)
    llr_voted = math.log((1.0 - p_free_surf) / (1.0 - p_free_water))
    print(f"surface voxels {n_surf}: voted {surf_v} frames, freed {surf_f}; P(freed|surface) = {p_free_surf:.3f}")
    print(f"voted water voxels {n_water}: voted {water_v} frames, freed {water_f}; "
          f"P(freed|voted water) = {p_free_water:.3f}")
    print(f"LLR(voted) = {llr_voted:+.2f}  LLR(freed) = {llr_free:+.2f}  |LLR(freed)|/LLR(voted) = "
          f"{-llr_free / llr_voted:.2f}")


if __name__ == "__main__":
    main()
