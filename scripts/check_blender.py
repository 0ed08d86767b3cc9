"""Checks that Blender imports a vdblight .vdb as RGB vector grids (its SH bands 0..2: nine).

Usage: blender -b --factory-startup --python scripts/check_blender.py -- FILE.vdb [--expect r,g,b]

Blender 3.4's Python API exposes, per grid: name, data_type, channels, matrix_object (index
to object space) and load(); it exposes neither voxel values nor the file metadata. So the
script checks, through Blender: the volume imports and loads without error, the nine SH
grids of bands 0..2 exist, they and every other SH grid in the file (bands 3..4 of the
default's SH order 4) have data_type 'VECTOR_FLOAT' and 3 channels, each grid loads, and
every grid puts voxel (i, j, k) at origin + spacing * (i, j, k) of level 0 (the same for all).
Metadata (format version, basis, origin, spacing) and the sh_l0m0 value (--expect) are
checked with pyopenvdb inside Blender's Python when it can be imported (Debian's Blender
runs the system Python 3.11, which has it); the origin/spacing from the metadata are then
compared with Blender's matrix. Exit status 0 on success, 1 with a one-line message.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import check_pyopenvdb as common  # noqa: E402  (SH_GRIDS, CheckError, the pyopenvdb checks)


def blender_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    import argparse
    parser = argparse.ArgumentParser(prog="check_blender.py")
    parser.add_argument("file")
    parser.add_argument("--expect", type=common.parse_rgb, help="expected sh_l0m0 at voxel (0,0,0) as r,g,b")
    return parser.parse_args(argv)


def level0_placement(grid):
    """(origin, spacing) from a grid's index-to-object matrix; requires a uniform scale."""
    m = grid.matrix_object
    spacing = m[0][0]
    off_diagonal = [m[r][c] for r in range(3) for c in range(3) if r != c]
    if any(abs(x) > 1e-12 for x in off_diagonal) or not all(common.close(m[a][a], spacing, 1e-9) for a in range(3)):
        raise common.CheckError("grid %s has a non-uniform or rotated transform %s" % (grid.name, list(map(list, m))))
    return (m[0][3], m[1][3], m[2][3]), spacing


def check_with_blender(path):
    import bpy
    if not os.path.isfile(path):
        raise common.CheckError("no such file")
    bpy.ops.object.volume_import(filepath=path)
    obj = bpy.context.active_object
    if obj is None or obj.type != 'VOLUME':
        raise common.CheckError("volume_import did not create a volume object")
    grids = obj.data.grids
    if not grids.load() or grids.error_message:
        raise common.CheckError("Blender cannot load the file: %s" % grids.error_message)
    by_name = {g.name: g for g in grids}
    placements = set()
    names = common.SH_GRIDS + sorted(n for n in by_name if n.startswith("sh_l") and n not in common.SH_GRIDS)
    if "sh_l0m0" not in by_name:  # an irradiance-vector volume (photon pass): its iv_* / ivc_* grids
        names = sorted(n for n in by_name if n.startswith("iv_") or n.startswith("ivc_")) or names
    for name in names:
        grid = by_name.get(name)
        if grid is None:
            raise common.CheckError("Blender sees no grid %s (grids: %s)" % (name, ", ".join(sorted(by_name))))
        if grid.data_type != 'VECTOR_FLOAT' or grid.channels != 3:
            raise common.CheckError("grid %s is %s with %d channels, expected VECTOR_FLOAT with 3"
                                    % (name, grid.data_type, grid.channels))
        if not grid.load():
            raise common.CheckError("Blender cannot load the voxels of grid %s: %s" % (name, grids.error_message))
        placements.add(level0_placement(grid))
    if len(placements) != 1:
        raise common.CheckError("the channel grids have different transforms: %s" % placements)
    return placements.pop(), len(names)


def main():
    args = blender_args()
    try:
        (origin, spacing), count = check_with_blender(args.file)
        summary = "Blender: %d VECTOR_FLOAT grids, voxel (0,0,0) at %s, spacing %g" % (count, tuple(origin), spacing)
        try:
            import pyopenvdb as vdb
        except ImportError:
            summary += "; pyopenvdb not importable in Blender: metadata and values NOT checked"
            if args.expect is not None:
                raise common.CheckError("--expect needs pyopenvdb, which Blender's Python cannot import")
        else:
            summary += "; pyopenvdb: " + common.check_with_pyopenvdb(args.file, args.expect)
            meta = vdb.readMetadata(args.file)
            meta_origin, meta_spacing = meta["vdblight:level0_origin"], meta["vdblight:level0_spacing"]
            if not common.close(spacing, meta_spacing, 1e-6) or \
                    any(abs(a - b) > 1e-6 * max(1.0, abs(b)) for a, b in zip(origin, meta_origin)):
                raise common.CheckError("Blender places voxel (0,0,0) at %s with spacing %g, metadata says %s, %g"
                                        % (tuple(origin), spacing, meta_origin, meta_spacing))
    except Exception as e:  # Blender exits with status 0 after an uncaught script error
        print("check_blender: FAIL: %s: %s" % (args.file, e), file=sys.stderr)
        sys.stderr.flush()
        os._exit(1)  # sys.exit inside Blender may be swallowed; leave with the status for sure
    print("check_blender: OK: %s: %s" % (args.file, summary))
    sys.stdout.flush()
    os._exit(0)


main()
