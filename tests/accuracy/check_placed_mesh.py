#!/usr/bin/env python3
"""A mesh brought from another project, used as it is: the suite's low mine written as a binary
STL in millimetres, y up, about its own centroid (as CAD tools and other simulators export), and
placed by the scenario (`scale`, `rpy_deg`, `position`; docs/scenario-format.md). sf-sim, the fused
sf-mapper and sf-eval run on it and on the original scenario (the mine's OBJ in world metres); the
two runs must give the same map and the same evaluation. The passes are cut to 800 sequences
each (about 10 s in all).

usage: check_placed_mesh.py OUTDIR SF_SIM SF_MAPPER SF_EVAL
"""
import json
import os
import struct
import subprocess
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SCENARIO = os.path.join(ROOT, "scenarios", "suite", "mine_low_cyl_two_passes.yaml")
MESHES = os.path.join(ROOT, "scenarios", "suite", "meshes")
MAPPER_YAML = os.path.join(ROOT, "scenarios", "mapper.yaml")
OBJECT_LINE = "- {file: meshes/mine_mine.obj, role: object, impedance: 45.0}"
SEQUENCES = "sequences: 1600"


def read_obj(path):
    vertices, triangles = [], []
    for line in open(path):
        t = line.split()
        if not t:
            continue
        if t[0] == "v":
            vertices.append(tuple(float(x) for x in t[1:4]))
        elif t[0] == "f":
            idx = [int(x.split("/")[0]) - 1 for x in t[1:]]
            triangles += [(idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1)]
    return vertices, triangles


def write_binary_stl(path, vertices, triangles, to_file):
    """One facet per triangle, every corner repeated (as STL stores them), normals left 0."""
    out = bytearray(b"placed-mesh test: the suite's mine in mm, y up".ljust(80, b" "))
    out += struct.pack("<I", len(triangles))
    for tri in triangles:
        out += struct.pack("<3f", 0.0, 0.0, 0.0)
        for i in tri:
            out += struct.pack("<3f", *to_file(vertices[i]))
        out += b"\0\0"
    with open(path, "wb") as f:
        f.write(out)


def run(cmd, log):
    with open(log, "w") as so:
        rc = subprocess.run(cmd, stdout=so, stderr=subprocess.STDOUT).returncode
    if rc != 0:
        sys.exit(f"FAIL: {' '.join(cmd)} exited {rc} (see {log})")


def main(out, sim, mapper, evaluator):
    os.makedirs(out, exist_ok=True)
    text = open(SCENARIO).read()
    if OBJECT_LINE not in text or text.count(SEQUENCES) != 2:
        sys.exit(f"FAIL: {SCENARIO} no longer has the lines this test edits")
    text = text.replace(SEQUENCES, "sequences: 800").replace("meshes/", MESHES + "/")
    vertices, triangles = read_obj(os.path.join(MESHES, "mine_mine.obj"))
    centre = [sum(v[k] for v in vertices) / len(vertices) for k in range(3)]
    # World (NED, m) to the file: millimetres about the centroid, y up. The scenario's
    # rpy_deg [-90, 0, 0] takes the file's +y to NED -z (up) and its +z to NED +y.
    def to_file(v):
        x, y, z = (v[k] - centre[k] for k in range(3))
        return (1000.0 * x, -1000.0 * z, 1000.0 * y)

    stl = os.path.join(out, "mine_mm_y_up.stl")
    write_binary_stl(stl, vertices, triangles, to_file)
    placed_line = (f"- {{file: {stl}, role: object, impedance: 45.0, scale: 0.001, rpy_deg: [-90, 0, 0], "
                   f"position: [{centre[0]!r}, {centre[1]!r}, {centre[2]!r}]}}")
    scenarios = {"world_obj": text, "placed_stl": text.replace(OBJECT_LINE, placed_line)}
    reports = {}
    for name, body in scenarios.items():
        yaml_path = os.path.join(out, name + ".yaml")
        with open(yaml_path, "w") as f:
            f.write(body)
        log, m, rep = (os.path.join(out, name + ext) for ext in (".lcmlog", ".map", ".json"))
        run([sim, "--scenario", yaml_path, "--log", log, "--quiet"], os.path.join(out, name + ".sim.txt"))
        run([mapper, "--config", MAPPER_YAML, "--log", log, "--map-out", m, "--variant", "fused"],
            os.path.join(out, name + ".mapper.txt"))
        run([evaluator, "--scenario", yaml_path, "--config", MAPPER_YAML, "--map", "fused=" + m, "--json", rep],
            os.path.join(out, name + ".eval.txt"))
        os.remove(log)
        reports[name] = json.load(open(rep))["variants"]["fused"]

    failures = []

    def bar(ok, what):
        print(("ok    " if ok else "FAIL  ") + what)
        if not ok:
            failures.append(what)

    a, b = reports["world_obj"], reports["placed_stl"]
    for key in ("precision", "recall_visible", "chamfer_cm"):
        bar(a[key] is not None and b[key] is not None and abs(a[key] - b[key]) <= 1e-3,
            f"fused {key}: placed STL {b[key]} vs OBJ in world metres {a[key]}")
    for key in ("truth_voxels", "visible_surface_voxels", "predicted_voxels", "objects"):
        bar(a["counts"].get(key) == b["counts"].get(key),
            f"{key}: placed STL {b['counts'].get(key)} vs OBJ in world metres {a['counts'].get(key)}")
    bar(a["precision"] is not None and a["precision"] > 0.5 and a["counts"].get("truth_voxels", 0) > 0,
        f"the mine is mapped at all (precision {a['precision']})")
    same = open(os.path.join(out, "world_obj.map"), "rb").read() == open(os.path.join(out, "placed_stl.map"), "rb").read()
    print(f"info  fused maps byte-identical: {same}")
    return 1 if failures else 0


if __name__ == "__main__":
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    sys.exit(main(*sys.argv[1:]))
