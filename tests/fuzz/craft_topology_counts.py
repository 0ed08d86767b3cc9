#!/usr/bin/python3
"""Writes a copy of a .vdb whose grid declares other tree topology counts: the tree's buffer
count, or its root node's tile or child count (the first words of the grid's topology, after
its compression flags, metadata and transform; OpenVDB 10, io::Archive::readGrid). This is how
the inputs of OpenVDB's slow read of a crafted tree were made (docs/measurements/robustness.md;
tests/vdb_topology_guard_test.cpp crafts the same in C++). The header UUID is replaced by a
random-shaped (version 4) one, so that vdblight's damage check (docs/format.md, "Damaged
files") lets the file reach OpenVDB, as one written by another program would.

    craft_topology_counts.py IN.vdb OUT.vdb GRID [--buffers N] [--tiles N] [--children N]
"""
import argparse
import struct

# The value size of a tree type ("Tree_vec3s_5_4_3"): the root's background and tiles hold one.
VALUE_BYTES = {"bool": 1, "mask": 1, "float": 4, "double": 8, "int32": 4, "int64": 8, "vec3s": 12, "vec3d": 24,
               "vec3i": 12, "ptidx32": 4, "ptidx64": 8, "ptdataidx32": 4, "ptdataidx64": 8}
# Bytes each map type reads after its name (math/Maps.h: Vec3d = 24 bytes, Mat4d = 128).
MAP_BYTES = {"UniformScaleTranslateMap": 144, "ScaleTranslateMap": 144, "UniformScaleMap": 120, "ScaleMap": 120,
             "TranslationMap": 24, "AffineMap": 128}


class Reader:
    def __init__(self, data, at=0):
        self.data, self.at = data, at

    def take(self, fmt):
        values = struct.unpack_from("<" + fmt, self.data, self.at)
        self.at += struct.calcsize("<" + fmt)
        return values[0] if len(values) == 1 else values

    def string(self):
        n = self.take("I")
        s = self.data[self.at:self.at + n].decode("latin-1")
        self.at += n
        return s

    def skip_meta_map(self):
        for _ in range(self.take("i")):
            self.string()  # name
            self.string()  # type
            n = self.take("I")  # value
            self.at += n


def topology_offset(data, grid):
    """(offset of the buffer count, value bytes) of `grid`'s tree (file format 224)."""
    r = Reader(data, 8)
    version = r.take("I")
    assert version >= 222, "file format %d: this script reads 222 and later" % version
    r.take("II")  # library version
    assert r.take("B") == 1, "no grid offsets"
    r.at += 36  # UUID
    r.skip_meta_map()
    for _ in range(r.take("i")):
        name, kind, parent = r.string(), r.string(), r.string()
        grid_pos, _block_pos, end_pos = r.take("qqq")
        if name != grid:
            r.at = end_pos  # the next descriptor follows this grid's data
            continue
        assert not parent, "an instance has no tree of its own"
        g = Reader(data, grid_pos + 4)  # after the compression flags
        g.skip_meta_map()
        map_type = g.string()
        g.at += MAP_BYTES[map_type]
        value = kind.replace("_HalfFloat", "").split("_")[1]
        return g.at, VALUE_BYTES[value]
    raise SystemExit("no grid '%s'" % grid)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("grid")
    ap.add_argument("--buffers", type=int)
    ap.add_argument("--tiles", type=int)
    ap.add_argument("--children", type=int)
    a = ap.parse_args()
    data = bytearray(open(a.input, "rb").read())
    at, value_bytes = topology_offset(bytes(data), a.grid)
    counts = at + 4 + value_bytes  # buffer count (int32), background, then tiles and children (uint32)
    old = struct.unpack_from("<iII", data, at)[0], *struct.unpack_from("<II", data, counts)
    if a.buffers is not None:
        struct.pack_into("<i", data, at, a.buffers)
    if a.tiles is not None:
        struct.pack_into("<I", data, counts, a.tiles)
    if a.children is not None:
        struct.pack_into("<I", data, counts + 4, a.children)
    data[21:57] = b"0badc0de-0000-4000-8000-000000000000"  # version 4, variant 10: not content-derived
    open(a.output, "wb").write(data)
    print("%s: grid '%s' topology at byte %d: buffers %d, root tiles %d, children %d (was %d, %d, %d)"
          % (a.output, a.grid, at, *struct.unpack_from("<i", data, at), *struct.unpack_from("<II", data, counts), *old))


if __name__ == "__main__":
    main()
