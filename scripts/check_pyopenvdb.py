#!/usr/bin/env python3
"""Checks a vdblight .vdb with pyopenvdb (an independent reader of the file format).

Usage: /usr/bin/python3 scripts/check_pyopenvdb.py FILE.vdb [--expect r,g,b] [--depth]

Checks that the file metadata has vdblight:format_version and a real-SH vdblight:basis
("sh2", or "sh:N" with N = 1..4: the default bake stores "sh:4"), that the basis's SH grids
((N + 1)^2 of them, named sh_l<l>m<m>) exist as Vec3 float grids in the order of
vdblight:channels, that their voxel (0, 0, 0) is active and sits at the level-0 origin with the level-0 spacing,
and that sh_l0m0 at voxel (0, 0, 0) is finite (and equals --expect within 1e-5 relative).
Irradiance-vector volumes (`bake --method photons`, basis irradiance_vectors: 18 grids iv_*;
irradiance_vectors_compact: 12 grids ivc_*) are checked the same way with their first grid
in place of sh_l0m0.
With --depth, also that the four depth-moment grids (docs/format.md) are vec3s grids with
voxel (0, 0, 0) active and every component in [0, 1].
Exit status 0 on success; otherwise 1 with a one-line message on stderr.
(On Debian, pyopenvdb is in /usr/bin/python3's dist-packages, not in other interpreters.)
"""
import argparse
import math
import sys

def sh_grid_names(order):
    """The grids of real SH bands 0..order, in channel order (docs/format.md)."""
    return ["sh_l%dm%s%d" % (l, "_neg" if m < 0 else "", abs(m)) for l in range(order + 1) for m in range(-l, l + 1)]


# Bands 0..2: every real-SH volume of order 2 or more has these nine (Blender checks them).
SH_GRIDS = sh_grid_names(2)
SH_ORDERS = {"sh2": 2, "sh:1": 1, "sh:2": 2, "sh:3": 3, "sh:4": 4}
SUPPORTED_FORMAT_VERSION = 1
# Irradiance-vector bases (photon pass) and their channel grids' prefix and count.
IV_BASES = {"irradiance_vectors": ("iv_", 18), "irradiance_vectors_compact": ("ivc_", 12)}


class CheckError(Exception):
    pass


def parse_rgb(text):
    parts = text.split(",")
    if len(parts) != 3:
        raise argparse.ArgumentTypeError("expected r,g,b, got %r" % text)
    return tuple(float(p) for p in parts)


def close(value, expected, rel=1e-5):
    return abs(value - expected) <= rel * max(abs(expected), 1e-30)


DEPTH_GRIDS = ["depth_mean_pos", "depth_mean_neg", "depth_sigma_pos", "depth_sigma_neg"]


def check_depth(vdb, path, types):
    for name in DEPTH_GRIDS:
        if types.get(name) != "vec3s":
            raise CheckError("depth grid %s is missing or not vec3s (grids: %s)" % (name, ", ".join(sorted(types))))
        grid = vdb.read(path, name)
        value, active = grid.getConstAccessor().probeValue((0, 0, 0))
        if not active:
            raise CheckError("voxel (0,0,0) of %s is not active" % name)
        lo, hi = grid.evalMinMax()
        if min(lo) < 0.0 or max(hi) > 1.0:
            raise CheckError("%s has values outside [0, 1]: %s .. %s" % (name, lo, hi))


def check_with_pyopenvdb(path, expect=None, depth=False):
    """Runs every check; returns a short summary or raises CheckError."""
    import pyopenvdb as vdb

    try:
        meta = vdb.readMetadata(path)
    except Exception as e:  # pyopenvdb raises plain exceptions for I/O and format errors
        raise CheckError("cannot read %s: %s" % (path, e))
    version = meta.get("vdblight:format_version")
    if not isinstance(version, int):
        raise CheckError("no integer vdblight:format_version metadata (not a vdblight volume)")
    if not 1 <= version <= SUPPORTED_FORMAT_VERSION:
        raise CheckError("unsupported vdblight:format_version %d" % version)
    basis = meta.get("vdblight:basis")
    channels = meta.get("vdblight:channels", "").split(",")
    if basis in SH_ORDERS:
        sh_grids = sh_grid_names(SH_ORDERS[basis])
        if channels != sh_grids:
            raise CheckError("vdblight:channels is %r" % meta.get("vdblight:channels"))
    elif basis in IV_BASES:
        prefix, count = IV_BASES[basis]
        sh_grids = channels  # the channel grids, checked like the SH ones below
        if len(channels) != count or not all(c.startswith(prefix) for c in channels):
            raise CheckError("vdblight:channels of basis %s is %r" % (basis, meta.get("vdblight:channels")))
    else:
        raise CheckError("vdblight:basis is %r, expected real SH (%s) or irradiance vectors (%s)" %
                         (basis, ", ".join(SH_ORDERS), ", ".join(IV_BASES)))
    first = sh_grids[0]
    origin = meta.get("vdblight:level0_origin")
    spacing = meta.get("vdblight:level0_spacing")
    if origin is None or spacing is None:
        raise CheckError("no vdblight:level0_origin / vdblight:level0_spacing metadata")

    types = {g.name: g.valueTypeName for g in vdb.readAllGridMetadata(path)}
    for name in sh_grids:
        if name not in types:
            raise CheckError("grid %s is missing (grids: %s)" % (name, ", ".join(sorted(types))))
        if types[name] != "vec3s":
            raise CheckError("grid %s has type %s, expected vec3s" % (name, types[name]))

    grid = vdb.read(path, first)
    value, active = grid.getConstAccessor().probeValue((0, 0, 0))
    if not active:
        raise CheckError("voxel (0,0,0) of %s is not active" % first)
    if not all(math.isfinite(c) for c in value):
        raise CheckError("%s at voxel (0,0,0) is not finite: %s" % (first, value))
    world = grid.transform.indexToWorld((0, 0, 0))
    if not all(close(w, o, 1e-9) or abs(w - o) < 1e-12 for w, o in zip(world, origin)):
        raise CheckError("voxel (0,0,0) is at %s, expected the level-0 origin %s" % (world, origin))
    if not all(close(s, spacing, 1e-9) for s in grid.transform.voxelSize()):
        raise CheckError("voxel size %s differs from vdblight:level0_spacing %r" % (grid.transform.voxelSize(), spacing))
    if expect is not None and not all(close(v, e) for v, e in zip(value, expect)):
        raise CheckError("%s at voxel (0,0,0) is %s, expected %s" % (first, value, expect))
    if depth:
        check_depth(vdb, path, types)
    return "format_version %d, basis %s, %d vec3s channel grids%s, %s(0,0,0) = (%.6g, %.6g, %.6g)" % (
        (version, basis, len(sh_grids), " + 4 depth grids" if depth else "", first) + tuple(value))


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file")
    parser.add_argument("--expect", type=parse_rgb, help="expected sh_l0m0 at voxel (0,0,0) as r,g,b")
    parser.add_argument("--depth", action="store_true", help="also check the depth-moment grids")
    args = parser.parse_args(argv)
    try:
        summary = check_with_pyopenvdb(args.file, args.expect, args.depth)
    except ImportError as e:
        print("check_pyopenvdb: FAIL: cannot import pyopenvdb (%s); use /usr/bin/python3" % e, file=sys.stderr)
        return 1
    except CheckError as e:
        print("check_pyopenvdb: FAIL: %s: %s" % (args.file, e), file=sys.stderr)
        return 1
    print("check_pyopenvdb: OK: %s: %s" % (args.file, summary))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
