#!/usr/bin/python3
"""Checks a `vdblight export --format vdb-preview` file with pyopenvdb (not vdblight's reader):
every voxel of irradiance_<dir> equals `vdblight query` at the voxel's world position for the
axis normal <dir>, irradiance_avg is the mean of the six, density is 1, and the grids follow
the conventions (vector_type invariant, names without dots).

    /usr/bin/python3 scripts/check_preview.py --cli build/bin/vdblight --volume v.vdb --preview DIR/preview.vdb

Exit status 0 on success, 1 with a message. Needs python3-openvdb and numpy.
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
import pyopenvdb as vdb

DIRS = {"xpos": (1, 0, 0), "xneg": (-1, 0, 0), "ypos": (0, 1, 0), "yneg": (0, -1, 0), "zpos": (0, 0, 1),
        "zneg": (0, 0, -1)}


def voxels(grid):
    """(index coords, values) of the active voxels, in a fixed order."""
    items = sorted((tuple(it.min), it.value) for it in grid.citerOnValues() if it.count == 1)
    return [c for c, _ in items], np.array([v for _, v in items], dtype=np.float64)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cli", required=True)
    ap.add_argument("--volume", required=True)
    ap.add_argument("--preview", required=True)
    args = ap.parse_args()
    grids = {g.name: g for g in vdb.readAllGridMetadata(args.preview)}
    want_names = ["irradiance_avg"] + ["irradiance_" + d for d in DIRS] + ["density"]
    if sorted(grids) != sorted(want_names):
        print("grids %s, expected %s" % (sorted(grids), sorted(want_names)))
        return 1
    loaded = {n: vdb.read(args.preview, n) for n in want_names}
    for n in want_names[:-1]:
        if loaded[n].metadata.get("vector_type") != "invariant" or "." in n:
            print("grid %s does not follow the conventions: %s" % (n, loaded[n].metadata))
            return 1
    coords, avg = voxels(loaded["irradiance_avg"])
    world = np.array([loaded["irradiance_avg"].transform.indexToWorld(c) for c in coords])
    rows, total, worst = [], np.zeros_like(avg), 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for d, n in DIRS.items():
            c2, values = voxels(loaded["irradiance_" + d])
            if c2 != coords:
                print("irradiance_%s has other voxels than irradiance_avg" % d)
                return 1
            csv = os.path.join(tmp, "p.csv")
            np.savetxt(csv, np.column_stack([world, np.tile(n, (len(world), 1))]), delimiter=",", fmt="%.9g",
                       header="x,y,z,nx,ny,nz", comments="")
            subprocess.run([args.cli, "query", args.volume, "--raw", "--points", csv, "-o", csv + ".out"], check=True)
            want = np.loadtxt(csv + ".out", delimiter=",", skiprows=1, ndmin=2)[:, 6:9]
            # Relative to the grid's largest value: at dark nodes (inside objects) E is only the
            # float rounding of the query's interpolation.
            rel = np.abs(values - want) / (np.abs(want).max() + 1e-30)
            if os.environ.get("DEBUG"):
                i = int(np.argmax(rel.max(axis=1))); print(d, coords[i], world[i], values[i], want[i])
            worst = max(worst, float(np.max(rel)))
            total += values
    worst_avg = float(np.max(np.abs(avg - total / 6) / (1e-6 + np.abs(total / 6))))
    dc, dv = voxels(loaded["density"])
    ok = worst < 1e-5 and worst_avg < 1e-5 and dc == coords and np.all(dv == 1.0) and len(coords) > 0
    print("%d voxels: max error vs query relative to the largest value %.3g, avg vs mean of six %.3g, density %s" % (
        len(coords), worst, worst_avg, "ok" if dc == coords and np.all(dv == 1.0) else "WRONG"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
