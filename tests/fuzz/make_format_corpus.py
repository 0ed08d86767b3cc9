#!/usr/bin/python3
"""Writes the seed corpora of the fuzz harnesses for the formats read through Assimp since
issue 14 (tests/fuzz/corpus/fuzz_scene_{fbx,dae,stl,off,x,3ds}/): small hand-written OFF, .x,
3DS and ASCII FBX files, and memory regression inputs with absurd declared counts. The FBX
(binary), COLLADA and STL seeds are Blender 3.4's exports of its default scene, written once
with `blender -b --factory-startup` (export_scene.fbx, wm.collada_export, export_mesh.stl) and
kept as files. Run from anywhere:

    /usr/bin/python3 tests/fuzz/make_format_corpus.py
"""
import os
import re
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def out(harness, name, data):
    d = os.path.join(HERE, "corpus", harness)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


out("fuzz_scene_off", "cube.off", "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
    "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n")
out("fuzz_scene_off", "regression-mem-counts.off", "OFF\n900000000 900000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
out("fuzz_scene_x", "quad.x",
    "xof 0303txt 0032\n"
    "Mesh Quad {\n 4;\n 0.0;0.0;1.0;,\n 2.0;0.0;1.0;,\n 2.0;1.0;1.0;,\n 0.0;1.0;1.0;;\n"
    " 1;\n 4;0,1,2,3;;\n"
    " MeshMaterialList {\n  1;\n  1;\n  0;;\n"
    "  Material Paint {\n   0.1;0.2;0.3;1.0;;\n   10.0;\n   0.0;0.0;0.0;;\n   0.0;0.0;0.0;;\n  }\n }\n}\n")
out("fuzz_scene_x", "regression-mem-vertex-count.x",
    "xof 0303txt 0032\nMesh Quad {\n 400000000;\n 0.0;0.0;1.0;,\n 2.0;0.0;1.0;;\n 1;\n 3;0,1,0;;\n}\n")


def chunk(cid, body):
    return struct.pack("<HI", cid, 6 + len(body)) + body


verts = struct.pack("<H", 4) + b"".join(struct.pack("<3f", *p) for p in [(0, 0, 0), (2, 0, 0), (2, 1, 0), (0, 1, 0)])
faces = struct.pack("<H", 2) + struct.pack("<8H", 0, 1, 2, 0, 0, 2, 3, 0)
mesh = chunk(0x4100, chunk(0x4110, verts) + chunk(0x4120, faces))
out("fuzz_scene_3ds", "quad.3ds", chunk(0x4D4D, chunk(0x3D3D, chunk(0x4000, b"Quad\0" + mesh))))

# The hand-written ASCII FBX of tests/scene_formats_handwritten_test.cpp (Blender writes binary only).
with open(os.path.join(ROOT, "tests", "scene_formats_handwritten_test.cpp")) as f:
    ascii_fbx = re.search(r'R"FBX\((.*?)\)FBX"', f.read(), re.S).group(1)
out("fuzz_scene_fbx", "quad_ascii.fbx", ascii_fbx)
out("fuzz_scene_fbx", "regression-mem-ascii-array-count.fbx", ascii_fbx.replace("Vertices: *12", "Vertices: *900000000"))
out("fuzz_scene_dae", "regression-mem-float-array-count.dae",
    '<?xml version="1.0"?>\n<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">'
    '<library_geometries><geometry id="g"><mesh><source id="p"><float_array id="pa" count="900000000">'
    '0 0 0 1 0 0 0 1 0</float_array></source></mesh></geometry></library_geometries></COLLADA>\n')
stl = b"\0" * 80 + struct.pack("<I", 900000000) + b"\0" * 50
out("fuzz_scene_stl", "regression-mem-triangle-count.stl", stl)
