#!/usr/bin/env python3
"""Scenes for the scale model of docs/scaling.md ("A scale model"), written into DIR:

  terrain.gltf   64 m x 64 m heightfield of 1 m quads + six box buildings 9..20 m tall,
                 albedo 0.4, a directional sun (KHR_lights_punctual) at 40 degrees elevation
  flat.obj       the same heightfield alone
  grid501.ply    a 250 m heightfield of 0.5 M triangles (ray cost and memory per triangle)
  grid1001.ply   a 500 m heightfield of 2 M triangles

usage: make_scenes.py DIR
"""
import base64, json, math, os, struct, sys

N = 64


def height(x, z):
    return 1.5 * math.sin(x * 0.11) * math.cos(z * 0.07) + 0.8 * math.sin(0.23 * x + 0.31 * z)


def heightfield():
    v = [(float(i), height(i, j), float(j)) for j in range(N + 1) for i in range(N + 1)]
    f = []
    for j in range(N):
        for i in range(N):
            a = j * (N + 1) + i
            f += [(a, a + N + 1, a + 1), (a + 1, a + N + 1, a + N + 2)]
    return v, f


def add_box(v, f, x0, z0, w, d, h):
    y0 = height(x0, z0) - 1
    base = len(v)
    for p in [(x0, y0, z0), (x0 + w, y0, z0), (x0 + w, y0, z0 + d), (x0, y0, z0 + d),
              (x0, y0 + h, z0), (x0 + w, y0 + h, z0), (x0 + w, y0 + h, z0 + d), (x0, y0 + h, z0 + d)]:
        v.append(tuple(map(float, p)))
    for a, b, c, e in [(0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7), (4, 5, 6, 7)]:
        f += [(base + a, base + b, base + c), (base + a, base + c, base + e)]


def qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return (w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2)


def write_gltf(path, v, f):
    pos = b"".join(struct.pack("<3f", *p) for p in v)
    idx = b"".join(struct.pack("<3I", *t) for t in f)
    buf = pos + idx
    ax, ay = math.radians(-50), math.radians(30)  # the light shines along its node's -Z
    q = qmul((math.cos(ay / 2), 0, math.sin(ay / 2), 0), (math.cos(ax / 2), math.sin(ax / 2), 0, 0))
    g = {"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_lights_punctual"],
         "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "color": [1, 0.95, 0.9], "intensity": 3.0}]}},
         "scene": 0, "scenes": [{"nodes": [0, 1]}],
         "nodes": [{"mesh": 0}, {"rotation": [q[1], q[2], q[3], q[0]], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
         "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
         "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.4, 0.4, 0.35, 1], "metallicFactor": 0}}],
         "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
         "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
                         {"buffer": 0, "byteOffset": len(pos), "byteLength": len(idx)}],
         "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(v), "type": "VEC3",
                        "min": [min(p[a] for p in v) for a in range(3)], "max": [max(p[a] for p in v) for a in range(3)]},
                       {"bufferView": 1, "componentType": 5125, "count": 3 * len(f), "type": "SCALAR"}]}
    with open(path, "w") as out:
        json.dump(g, out)


def write_obj(path, v, f):
    with open(path, "w") as out:
        for p in v:
            out.write("v %.4f %.4f %.4f\n" % p)
        for t in f:
            out.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


def write_grid_ply(path, n):
    with open(path, "wb") as out:
        out.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
                   "property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n"
                   % (n * n, 2 * (n - 1) * (n - 1))).encode())
        out.write(b"".join(struct.pack("<3f", i * 0.5, math.sin(i * 0.05) * math.cos(j * 0.07), j * 0.5)
                           for j in range(n) for i in range(n)))
        faces = bytearray()
        for j in range(n - 1):
            for i in range(n - 1):
                a = j * n + i
                faces += struct.pack("<B3i", 3, a, a + n, a + 1) + struct.pack("<B3i", 3, a + 1, a + n, a + n + 1)
        out.write(faces)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    d = sys.argv[1]
    os.makedirs(d, exist_ok=True)
    v, f = heightfield()
    write_obj(os.path.join(d, "flat.obj"), v, f)
    for box in [(8, 8, 10, 8, 12), (30, 6, 8, 14, 18), (48, 10, 10, 10, 9), (10, 36, 14, 10, 15), (34, 34, 9, 9, 20),
                (50, 44, 8, 12, 11)]:
        add_box(v, f, *box)
    write_gltf(os.path.join(d, "terrain.gltf"), v, f)
    write_grid_ply(os.path.join(d, "grid501.ply"), 501)
    write_grid_ply(os.path.join(d, "grid1001.ply"), 1001)


if __name__ == "__main__":
    main()
