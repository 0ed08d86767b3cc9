#!/usr/bin/python3
"""Writes the memory-bound regression inputs (tests/fuzz/corpus/<harness>/regression-mem-*):
small scene files whose declared sizes (accessor counts, byte lengths, node instancing,
array counts) would make Assimp allocate gigabytes. Each must be refused with one line,
within the loader's memory bound (docs/scene.md, "Memory bound"; tests/scene_memory_bound_test.cpp
runs each in a child process and checks its peak resident memory; scripts/fuzz.sh replays
them under a 256 MB malloc limit). Run from anywhere:

    /usr/bin/python3 tests/fuzz/make_memory_corpus.py
"""
import base64
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def out(harness, name, data):
    d = os.path.join(HERE, "corpus", harness)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "regression-mem-" + name), "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


def glb(doc, body=b""):
    j = json.dumps(doc, separators=(",", ":")).encode()
    j += b" " * (-len(j) % 4)
    chunks = struct.pack("<I4s", len(j), b"JSON") + j
    if body:
        body += b"\0" * (-len(body) % 4)
        chunks += struct.pack("<I4s", len(body), b"BIN\0") + body
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


TRIANGLE = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)


def triangle_doc():
    return {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "buffers": [{"byteLength": len(TRIANGLE)}],
            "bufferViews": [{"buffer": 0, "byteLength": len(TRIANGLE)}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                           "min": [0, 0, 0], "max": [1, 1, 0]}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}]}


# An accessor without a buffer view is zero-filled at its declared count: 1.2 GB.
d = triangle_doc()
d["accessors"][0] = {"componentType": 5126, "count": 100000000, "type": "VEC3"}
out("fuzz_scene_glb", "accessor-without-view.glb", glb(d, TRIANGLE))
# An index accessor without a view: 300 M indices.
d = triangle_doc()
d["meshes"][0]["primitives"][0]["indices"] = 1
d["accessors"].append({"componentType": 5125, "count": 300000000, "type": "SCALAR"})
out("fuzz_scene_glb", "indices-without-view.glb", glb(d, TRIANGLE))
# A count far past its buffer view.
d = triangle_doc()
d["accessors"][0]["count"] = 100000000
out("fuzz_scene_glb", "accessor-count-past-view.glb", glb(d, TRIANGLE))
# A buffer declaring 2 GB in a file of a few hundred bytes.
d = triangle_doc()
d["buffers"][0]["byteLength"] = 2 ** 31
out("fuzz_scene_glb", "buffer-length.glb", glb(d, TRIANGLE))
# A chunk length past the end of the file.
g = bytearray(glb(triangle_doc(), TRIANGLE))
g[12:16] = struct.pack("<I", 2 ** 31)
out("fuzz_scene_glb", "chunk-length.glb", bytes(g))
# Eight levels of nodes that list the same child ten times: 10^8 instances of one mesh.
d = triangle_doc()
d["nodes"] = [{"children": [1] * 10}] + [{"children": [i + 2] * 10} for i in range(7)] + [{"mesh": 0}]
out("fuzz_scene_glb", "node-instancing.glb", glb(d, TRIANGLE))
# A node hierarchy with a cycle.
d = triangle_doc()
d["nodes"] = [{"children": [1]}, {"children": [0], "mesh": 0}]
out("fuzz_scene_glb", "node-cycle.glb", glb(d, TRIANGLE))
# The same accessor case in a .gltf with an embedded buffer.
d = triangle_doc()
d["accessors"][0] = {"componentType": 5126, "count": 100000000, "type": "VEC3"}
d["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(TRIANGLE).decode()
out("fuzz_scene_gltf", "accessor-without-view.gltf", json.dumps(d))
d = triangle_doc()
d["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(TRIANGLE).decode()
d["buffers"][0]["byteLength"] = 2 ** 31
out("fuzz_scene_gltf", "buffer-length.gltf", json.dumps(d))
