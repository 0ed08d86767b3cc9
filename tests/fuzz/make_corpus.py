#!/usr/bin/python3
"""Writes the scene seed corpora of the fuzz harnesses (tests/fuzz/corpus/fuzz_scene_*/):
small valid OBJ, PLY, glTF and GLB scenes covering what the loader reads (materials with
emission and KHR_materials_emissive_strength, punctual lights, node transforms including a
mirror, quads to triangulate, normals/texcoords). The .vdb seeds come from
tests/fuzz/make_vdb_corpus.sh (it needs the built CLI). Run from anywhere:

    /usr/bin/python3 tests/fuzz/make_corpus.py
"""
import base64
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def out(harness, name, data):
    d = os.path.join(HERE, "corpus", harness)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


# --- OBJ
with open(os.path.join(ROOT, "data", "cornell_box.obj")) as f:
    out("fuzz_scene_obj", "cornell_box.obj", f.read())
out("fuzz_scene_obj", "triangle.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
out("fuzz_scene_obj", "quad_negative_indices.obj",
    "o quad\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nusemtl floor\nf -4 -1 -2 -3\n")
out("fuzz_scene_obj", "normals_texcoords.obj",
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nvn 1 1 1\n"
    "g a\nusemtl m1\nf 1/1/1 2/2/1 3/3/1\ng b\nusemtl m2\nf 1//2 3//2 4//2\nf 2/1 3/2 4/3\n")
out("fuzz_scene_obj", "points_lines_degenerate.obj",
    "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\np 1\nl 1 2\nf 1 2 3\nf 1 2 4\nf 1 1 2\n")

# --- PLY
out("fuzz_scene_ply", "triangle_ascii.ply",
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
verts = [(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1), (0, 1, 0)]
header = ("ply\nformat binary_little_endian 1.0\ncomment seed\nelement vertex %d\nproperty float x\n"
          "property float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
          "element face 3\nproperty list uchar uint vertex_indices\nend_header\n" % len(verts))
body = b"".join(struct.pack("<3f3B", *v, 200, 100, 50) for v in verts)
body += struct.pack("<B4I", 4, 0, 3, 2, 1) + struct.pack("<B3I", 3, 0, 1, 4) + struct.pack("<B3I", 3, 1, 2, 4)
out("fuzz_scene_ply", "pyramid_binary.ply", header.encode() + body)
out("fuzz_scene_ply", "quad_ascii_normals.ply",
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
    "property float nx\nproperty float ny\nproperty float nz\nelement face 1\n"
    "property list uchar int vertex_indices\nend_header\n0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n"
    "4 0 1 2 3\n")

# --- glTF / GLB: two triangles (one indexed), materials, lights, transforms
positions = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
quad = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0)
indices = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
binary = positions + quad + indices


def gltf(uri, with_lights=True):
    doc = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [
            {"children": [1, 2, 3, 4, 5], "translation": [1, 2, 3], "rotation": [0, 0.70710678, 0, 0.70710678]},
            {"mesh": 0},
            {"mesh": 1, "scale": [-1, 1, 1]},
            {"translation": [0, 1, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"translation": [0, 0, 1], "extensions": {"KHR_lights_punctual": {"light": 1}}},
            {"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1],
             "extensions": {"KHR_lights_punctual": {"light": 2}}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]},
                   {"primitives": [{"attributes": {"POSITION": 1}, "indices": 2, "material": 1}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 84, "byteLength": 12}],
        "buffers": [dict({"byteLength": len(binary)}, **({"uri": uri} if uri else {}))],
        "materials": [
            {"name": "lamp", "doubleSided": True, "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1.0]},
             "emissiveFactor": [1.0, 0.5, 0.25],
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 5.0}}},
            {"name": "wall", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0]}}],
        "extensionsUsed": ["KHR_materials_emissive_strength"],
    }
    if with_lights:
        doc["extensionsUsed"].append("KHR_lights_punctual")
        doc["extensions"] = {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1.0, 0.5, 0.25], "intensity": 10},
            {"type": "spot", "color": [1, 1, 1], "intensity": 4, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}},
            {"type": "directional", "color": [0.5, 1, 1], "intensity": 3}]}}
    return json.dumps(doc, separators=(",", ":"))


data_uri = "data:application/octet-stream;base64," + base64.b64encode(binary).decode()
out("fuzz_scene_gltf", "lights_materials.gltf", gltf(data_uri))
out("fuzz_scene_gltf", "no_lights.gltf", gltf(data_uri, with_lights=False))
out("fuzz_scene_gltf", "minimal_triangle.gltf", json.dumps({
    "asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                   "min": [0, 0, 0], "max": [1, 1, 0]}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "buffers": [{"uri": "data:application/octet-stream;base64," + base64.b64encode(positions).decode(),
                 "byteLength": 36}]}, separators=(",", ":")))


def glb(json_text, bin_data):
    j = json_text.encode()
    j += b" " * (-len(j) % 4)
    b = bin_data + b"\0" * (-len(bin_data) % 4)
    return (b"glTF" + struct.pack("<II", 2, 12 + 8 + len(j) + 8 + len(b)) + struct.pack("<I", len(j)) + b"JSON" + j +
            struct.pack("<I", len(b)) + b"BIN\0" + b)


out("fuzz_scene_glb", "lights_materials.glb", glb(gltf(None), binary))
out("fuzz_scene_glb", "no_lights.glb", glb(gltf(None, with_lights=False), binary))
