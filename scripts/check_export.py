#!/usr/bin/python3
"""Round trip of `vdblight export`, outside the C++ code.

Reads the textures of an export directory using ONLY manifest.json and the formulas of
docs/engines.md (container headers are parsed from the KTX 2.0 / DDS specifications, not
taken from the manifest), evaluates irradiance at random points and normals with the
trilinear filtering a GPU does (clamp-to-edge, half-texel offset), and compares it with
`vdblight query` on the original volume.

    /usr/bin/python3 scripts/check_export.py --cli build/bin/vdblight --volume v.vdb --export outdir

Exit status 0 if every sample matches within the tolerance (1e-3 relative for half
textures, 1e-5 for float), 1 otherwise. Needs numpy (Debian: python3-numpy).

Layouts: sh2, sh2-packed, sh1 (SH volumes), sh1-16 and sh2-32 (SH volumes; each texel decoded
by the manifest's compact_sh.decode, then read as sh1 / sh2-packed; every point must lie
within the bound that the 8-bit rounding explains, plus the half-float tolerance), vectors (irradiance-vector volumes) and bins
(bins:R / moment:n volumes: the four-bin blend of the manifest's `bins.blend`, with the bin
of a direction found by the formulas of `bins.bin_of_direction`; a moment volume is queried
with --view 0,0,1) are matched against the query. compact (Pacanowski et al. section 4.2) is lossy: with
--vectors-export DIR (a float `vectors` export of the same volume) every compact texel is
checked against the section 4.2 encoding of the vectors texels; its error against the query
is printed, and checked only with --compact-tolerance. basis (`export --layout basis`) of a real-SH
volume (manifest `basis` sh2 or sh:N, N = 1..4): E = sum_j A_l L_j Y_j(n) with the explicit
polynomials of docs/engine_layouts.md ("Shaders for sh:N"), evaluated here, against the full query;
the basis layout of other bases (bins:R, moment:n) is refused with exit status 2.
"""
import argparse
import json
import math
import os
import struct
import subprocess
import sys
import tempfile

import numpy as np

KTX2_IDENTIFIER = bytes([0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A])


def read_ktx2(data, dtype):
    """Level 0 of a KTX 2.0 file: the level index entry at byte 80 gives offset and length."""
    if data[:12] != KTX2_IDENTIFIER:
        raise ValueError("not a KTX 2.0 file")
    vk_format, type_size, w, h, d, layers, faces, levels, scheme = struct.unpack_from("<9I", data, 12)
    if scheme != 0 or faces != 1 or layers != 0:
        raise ValueError("unexpected KTX2 header")
    offset, length, _ = struct.unpack_from("<3Q", data, 80)
    texels = np.frombuffer(data, dtype=dtype, count=length // np.dtype(dtype).itemsize, offset=offset)
    return texels.reshape(d, h, w, 4), vk_format


def read_dds(data, dtype):
    """DDS with the DX10 header: 4 + 124 + 20 bytes, then the texels."""
    if data[:4] != b"DDS " or struct.unpack_from("<I", data, 4)[0] != 124 or data[84:88] != b"DX10":
        raise ValueError("not a DDS file with a DX10 header")
    h, w, _, d = struct.unpack_from("<4I", data, 12)
    dxgi = struct.unpack_from("<I", data, 128)[0]
    texels = np.frombuffer(data, dtype=dtype, count=w * h * d * 4, offset=148)
    return texels.reshape(d, h, w, 4), dxgi


# Each texture's "format" (manifest version 2): numpy type, bytes per texel, VkFormat, DXGI_FORMAT.
TEXEL_FORMATS = {
    "rgba16_sfloat": ("<f2", 8, 97, 10),
    "rgba32_sfloat": ("<f4", 16, 109, 2),
    "rgba8_unorm": ("u1", 4, 37, 28),
}


def load_textures(manifest, directory):
    nx, ny, nz = manifest["dims"]
    fmt = manifest["format"]
    out = {}
    for tex in manifest["textures"]:
        dtype, texel_bytes, vk_format, dxgi_format = TEXEL_FORMATS[tex["format"]]
        if tex["bytes_per_texel"] != texel_bytes:
            raise ValueError("%s: bytes_per_texel %d for %s" % (tex["file"], tex["bytes_per_texel"], tex["format"]))
        with open(os.path.join(directory, tex["file"]), "rb") as f:
            data = f.read()
        if fmt == "raw":
            arr = np.frombuffer(data, dtype=dtype).reshape(nz, ny, nx, 4)
        elif fmt == "ktx2":
            arr, vk = read_ktx2(data, dtype)
            if vk != vk_format or vk != tex["vkFormat"]:
                raise ValueError("%s: vkFormat %d, manifest format %s" % (tex["file"], vk, tex["format"]))
        elif fmt == "dds":
            arr, dxgi = read_dds(data, dtype)
            if dxgi != dxgi_format or dxgi != tex["dxgiFormat"]:
                raise ValueError("%s: dxgiFormat %d, manifest format %s" % (tex["file"], dxgi, tex["format"]))
        else:
            raise ValueError("format %s is not read by this script (the EXR atlas is checked with OpenEXR)" % fmt)
        if arr.shape != (nz, ny, nx, 4):
            raise ValueError("%s has shape %s, manifest says %s" % (tex["file"], arr.shape, (nz, ny, nx, 4)))
        # An unorm texture samples as byte / 255 (what a GPU returns for it).
        out[tex["name"]] = arr.astype(np.float64) / 255.0 if dtype == "u1" else arr.astype(np.float64)
    return out


def sample_trilinear(tex, uvw, max_abs=False):
    """GPU linear filtering with clamp-to-edge: texel coordinate t = uvw * size - 0.5.
    With max_abs, the largest magnitude of the 8 texels instead (for the error scale)."""
    nz, ny, nx, _ = tex.shape
    size = np.array([nx, ny, nz], dtype=np.float64)
    t = uvw * size - 0.5
    i0 = np.floor(t).astype(np.int64)
    f = t - i0
    result = np.zeros((uvw.shape[0], 4))
    for corner in range(8):
        bits = np.array([(corner >> a) & 1 for a in range(3)])
        idx = np.clip(i0 + bits, 0, size.astype(np.int64) - 1)
        value = tex[idx[:, 2], idx[:, 1], idx[:, 0]]
        if max_abs:
            result = np.maximum(result, np.abs(value))
            continue
        w = np.prod(np.where(bits == 1, f, 1.0 - f), axis=1)
        result += w[:, None] * value
    return result


def depth_weights(manifest, textures, x):
    """docs/engine_visibility.md, visibility-aware lookup: the 8 corner texel indices and their weights
    (trilinear x (Chebyshev visibility^3 + floor), normalised) of a volume with depth moments."""
    d = manifest["depth"]
    dims = np.array(manifest["dims"], dtype=np.int64)
    spacing = np.array(manifest["texel_spacing"], dtype=np.float64)
    g = np.clip((x - np.array(manifest["bounds_min"])) / spacing, 0.0, (dims - 1).astype(np.float64))
    i0 = np.minimum(np.floor(g).astype(np.int64), np.maximum(dims - 2, 0))
    f = g - i0
    bias, min_sigma, floor = d["bias"], d["min_sigma"], d["floor"]
    idx, w = [], []
    for corner in range(8):
        bits = np.array([(corner >> a) & 1 for a in range(3)])
        p = np.minimum(i0 + bits, dims - 1)
        o = f - bits
        v = np.ones(len(x))
        for a, name in enumerate(d["textures"]):
            t = textures[name][p[:, 2], p[:, 1], p[:, 0]]
            neg = o[:, a] < 0
            mu = np.where(neg, t[:, 1], t[:, 0])
            sigma = np.where(neg, t[:, 3], t[:, 2])
            e = np.abs(o[:, a]) - mu - bias
            s2 = sigma * sigma + min_sigma * min_sigma
            v *= np.where(e <= 0, 1.0, s2 / (s2 + e * e))
        trilinear = np.prod(np.where(bits == 1, f, 1.0 - f), axis=1)
        idx.append(p)
        w.append(trilinear * (v ** 3 + floor))
    w = np.array(w)
    return idx, w / w.sum(axis=0)


def corner_weights(manifest, x):
    """The 8 corner texel indices and trilinear weights of points x (texel points at
    bounds_min + texel_spacing * i, clamped to the lattice): hardware filtering as corners."""
    dims = np.array(manifest["dims"], dtype=np.int64)
    g = np.clip((x - np.array(manifest["bounds_min"])) / np.array(manifest["texel_spacing"]), 0.0,
                (dims - 1).astype(np.float64))
    i0 = np.minimum(np.floor(g).astype(np.int64), np.maximum(dims - 2, 0))
    f = g - i0
    idx, w = [], []
    for corner in range(8):
        bits = np.array([(corner >> a) & 1 for a in range(3)])
        idx.append(np.minimum(i0 + bits, dims - 1))
        w.append(np.prod(np.where(bits == 1, f, 1.0 - f), axis=1))
    return idx, np.array(w)


def sample_weighted(tex, idx, w):
    return sum(w[c][:, None] * tex[idx[c][:, 2], idx[c][:, 1], idx[c][:, 0]] for c in range(8))


COMPACT_SH_LAYOUTS = ("sh1-16", "sh2-32")


def decode_compact_sh(manifest, textures):
    """sh1-16 / sh2-32 (manifest compact_sh.decode): every texel decoded into the textures of
    the layout it stands for (shAr..shAb for sh1-16 and shBr..shC too for sh2-32), so that
    they are then sampled (trilinear, or with the depth weights) and evaluated as sh1 /
    sh2-packed: blending the decoded corners, as docs/engine_layouts.md's shader does. Also returns
    per colour the texels' a (L0 term), which the quantisation bound scales with."""
    k = manifest["compact_sh"]
    t0, t1, t2 = textures["L0_L1Rx"], textures["L1G_L1Ry"], textures["L1B_L1Rz"]
    a = t0[..., :3]
    l1 = [np.stack([t0[..., 3], t1[..., 3], t2[..., 3]], axis=-1), t1[..., :3], t2[..., :3]]
    out = {}
    order2 = manifest["layout"] == "sh2-32"
    for c, name in enumerate("rgb"):
        ac = a[..., c:c + 1]
        b = (l1[c] - 0.5) * k["l1_range"] * ac
        d = np.zeros_like(ac)
        if order2:
            q = (textures["L2_" + name.upper()] - 0.5) * np.array(k["l2_range"]) * ac
            d = q[..., 2:3]
            out["shB" + name] = np.concatenate([q[..., 0:2], 3.0 * d, q[..., 3:4]], axis=-1)
        out["shA" + name] = np.concatenate([b, ac - d], axis=-1)
    if order2:
        c = (textures["L2_C"][..., :3] - 0.5) * k["l2c_range"] * a
        out["shC"] = np.concatenate([c, np.zeros_like(c[..., :1])], axis=-1)
    out["a"] = np.concatenate([a, np.zeros_like(a[..., :1])], axis=-1)
    for name, tex in textures.items():  # light visibility and depth as they are
        if name not in ("L0_L1Rx", "L1G_L1Ry", "L1B_L1Rz", "L2_R", "L2_G", "L2_B", "L2_C"):
            out[name] = tex
    return out


def quantisation_bound(manifest, textures, x, n):
    """The largest |E_export - E_query| that 8-bit rounding explains, per point and colour
    (docs/engine_layouts.md, sh1-16 / sh2-32): each stored t is within 1/510 of v / (range a) + 0.5,
    so the decoded v is within range * a / 510; E is a sum of such v times the normal's
    polynomial, and blending corners with weights summing to 1 keeps the bound. Light
    visibility (8-bit too) adds exact irradiance / 510 per listed light."""
    k = manifest["compact_sh"]
    x_, y_, z_ = np.abs(n[:, 0]), np.abs(n[:, 1]), np.abs(n[:, 2])
    per_a = k["l1_range"] * (x_ + y_ + z_)
    if manifest["layout"] == "sh2-32":
        r = k["l2_range"]
        per_a = per_a + r[0] * x_ * y_ + r[1] * y_ * z_ + r[3] * z_ * x_ + r[2] * np.abs(3 * z_ * z_ - 1)
        per_a = per_a + k["l2c_range"] * np.abs(x_ * x_ - y_ * y_)
    uvw = x * np.array(manifest["uvw_scale"]) + np.array(manifest["uvw_bias"])
    if manifest.get("depth", {}).get("exported"):
        a = sample_weighted(textures["a"], *depth_weights(manifest, textures, x))[:, :3]
    else:
        a = sample_trilinear(textures["a"], uvw)[:, :3]
    bound = a * (per_a / 510.0)[:, None]
    direct = manifest.get("direct", {"mode": "baked"})
    if direct["mode"] == "occlusion":
        for light in direct["lights"]:
            bound += np.array([np.abs(exact_irradiance(light, x[i], n[i])) for i in range(len(x))]) / 510.0
    return bound


def irradiance_terms(manifest, textures, x, n, max_abs=False):
    """docs/engine_layouts.md: the terms whose sum is E(x, n), per colour channel: shape (terms, points, 3)."""
    uvw = x * np.array(manifest["uvw_scale"]) + np.array(manifest["uvw_bias"])
    if manifest.get("depth", {}).get("exported") and not max_abs:
        # Depth moments: the basis texels blended with the visibility-aware weights (the
        # query's default); the visibility textures of listed lights too (direct_light).
        idx, w = depth_weights(manifest, textures, x)
        s = {name: sample_weighted(tex, idx, w) for name, tex in textures.items()}
    else:
        s = {name: sample_trilinear(tex, uvw, max_abs) for name, tex in textures.items()}
    layout = {"sh1-16": "sh1", "sh2-32": "sh2-packed"}.get(manifest["layout"], manifest["layout"])
    nx_, ny_, nz_ = n[:, 0], n[:, 1], n[:, 2]
    terms = []
    if layout in ("sh2-packed", "sh1"):
        n1 = [nx_, ny_, nz_, np.ones_like(nx_)]
        for i in range(4):
            terms.append(np.column_stack([s["shA" + c][:, i] * n1[i] for c in "rgb"]))
        if layout == "sh2-packed":
            quad = [nx_ * ny_, ny_ * nz_, nz_ * nz_, nz_ * nx_]
            for i in range(4):
                terms.append(np.column_stack([s["shB" + c][:, i] * quad[i] for c in "rgb"]))
            terms.append(s["shC"][:, :3] * (nx_ * nx_ - ny_ * ny_)[:, None])
        return np.array(terms)
    if layout == "sh2":
        k = manifest["constants"]
        a = [k["A0"], k["A1"], k["A1"], k["A1"], k["A2"], k["A2"], k["A2"], k["A2"], k["A2"]]
        y = [np.full_like(nx_, k["c0"]), k["c1"] * ny_, k["c1"] * nz_, k["c1"] * nx_, k["c2"] * nx_ * ny_,
             k["c2"] * ny_ * nz_, k["c3"] * (3 * nz_ * nz_ - 1), k["c2"] * nx_ * nz_, k["c4"] * (nx_ * nx_ - ny_ * ny_)]
        names = [t["name"] for t in manifest["textures"]]
        return np.array([a[j] * s[names[j]][:, :3] * y[j][:, None] for j in range(9)])
    if layout in ("vectors", "compact"):
        # docs/format.md "Reconstruction" (the query's default: the quadratic blend, clamped to the
        # bounds the vectors prove), per colour c:
        # E = 1/2 sum_a V_a n_a + 1/4 sum_ab G_ab n_a n_b + 1/4 sum_a G_aa n_a^2,
        # V_a = I_(a,pos)[a] + I_(a,neg)[a], G_ab = I_(a,pos)[b] - I_(a,neg)[b].
        def vec(d, c):  # (points, 3): I_d for colour c
            if layout == "vectors":
                return s["iv_%s_%s" % (d, c)][:, :3]
            # 4.2: I_c ~ colour.c * normalize(dir)
            dv = s["ivc_%s_dir" % d][:, :3]
            length = np.linalg.norm(dv, axis=1)
            unit = np.where(length[:, None] > 0, dv / np.where(length > 0, length, 1)[:, None], 0.0)
            return s["ivc_%s_colour" % d][:, "rgb".index(c)][:, None] * unit
        for a, axis in enumerate("xyz"):
            cols_v, cols_q = [], []
            for c in "rgb":
                pos, neg = vec(axis + "pos", c), vec(axis + "neg", c)
                if max_abs:  # the error scale: magnitudes add, nothing cancels
                    pos, neg = np.abs(pos), -np.abs(neg)
                cols_v.append(0.5 * ((pos[:, a] - neg[:, a]) if max_abs else (pos[:, a] + neg[:, a])) * n[:, a])
                g = pos - neg  # G_ab for b = 0..2
                q = 0.25 * g[:, a] * n[:, a] * n[:, a]
                for b in range(3):
                    q = q + 0.25 * g[:, b] * n[:, a] * n[:, b]
                cols_q.append(q)
            terms.append(np.column_stack(cols_v))
            terms.append(np.column_stack(cols_q))
        if not max_abs:
            # Clamped to what the vectors prove: max(0, max_d dot(I_d, n)) <= E <= sum_a |n_a| E_(a, sign n_a).
            quad = np.sum(terms, axis=0)
            lo, hi = np.zeros_like(quad), np.zeros_like(quad)
            for ci, c in enumerate("rgb"):
                for a, axis in enumerate("xyz"):
                    for sign in ("pos", "neg"):
                        lo[:, ci] = np.maximum(lo[:, ci], np.sum(vec(axis + sign, c) * n, axis=1))
                    e_pos, e_neg = vec(axis + "pos", c)[:, a], -vec(axis + "neg", c)[:, a]
                    hi[:, ci] += np.abs(n[:, a]) * np.where(n[:, a] < 0, e_neg, e_pos)
            terms.append(np.maximum(lo, np.minimum(quad, hi)) - quad)
        return np.array(terms)
    if layout == "bins":
        # The four-bin blend of the manifest's bins.blend (what `vdblight query` does), per point.
        R = manifest["bins"]["resolution"]
        names = [t["name"] for t in manifest["textures"]]
        h, u, v = direction_to_square(n)
        gu, gv = u * R - 0.5, v * R - 0.5
        iu0, iv0 = np.floor(gu).astype(np.int64), np.floor(gv).astype(np.int64)
        fu, fv = gu - iu0, gv - iv0
        values = np.stack([s[name][:, :3] for name in names])  # (bins, points, 3)
        rows = np.arange(len(n))
        for b in range(2):
            for a in range(2):
                iu, iv, hh = iu0 + a, iv0 + b, h.copy()
                out_u, out_v = (iu < 0) | (iu >= R), (iv < 0) | (iv >= R)
                hh = np.where(out_u, 1 - hh, hh)
                hh = np.where(out_v, 1 - hh, hh)
                iu, iv = np.clip(iu, 0, R - 1), np.clip(iv, 0, R - 1)
                channel = hh * R * R + iv * R + iu
                w = (fu if a else 1 - fu) * (fv if b else 1 - fv)
                terms.append(values[channel, rows] * w[:, None])
        return np.array(terms)
    if layout == "basis":
        return sh_basis_terms(manifest, s, n)
    raise ValueError("unknown layout " + layout)


# docs/engines.md "Shaders for sh:N": (l, m, constant, polynomial in the unit normal's x, y, z)
# of every real SH Y_lm up to band 4, orthonormal, without the Condon-Shortley phase.
SH_POLYNOMIALS = [
    (0, 0, 0.282094792, lambda x, y, z: np.ones_like(x)),
    (1, -1, 0.488602512, lambda x, y, z: y),
    (1, 0, 0.488602512, lambda x, y, z: z),
    (1, 1, 0.488602512, lambda x, y, z: x),
    (2, -2, 1.092548431, lambda x, y, z: x * y),
    (2, -1, 1.092548431, lambda x, y, z: y * z),
    (2, 0, 0.315391565, lambda x, y, z: 3 * z * z - 1),
    (2, 1, 1.092548431, lambda x, y, z: x * z),
    (2, 2, 0.546274215, lambda x, y, z: x * x - y * y),
    (3, -3, 0.590043590, lambda x, y, z: y * (3 * x * x - y * y)),
    (3, -2, 2.890611443, lambda x, y, z: x * y * z),
    (3, -1, 0.457045799, lambda x, y, z: y * (5 * z * z - 1)),
    (3, 0, 0.373176333, lambda x, y, z: z * (5 * z * z - 3)),
    (3, 1, 0.457045799, lambda x, y, z: x * (5 * z * z - 1)),
    (3, 2, 1.445305721, lambda x, y, z: z * (x * x - y * y)),
    (3, 3, 0.590043590, lambda x, y, z: x * (x * x - 3 * y * y)),
    (4, -4, 2.503342942, lambda x, y, z: x * y * (x * x - y * y)),
    (4, -3, 1.770130770, lambda x, y, z: y * z * (3 * x * x - y * y)),
    (4, -2, 0.946174696, lambda x, y, z: x * y * (7 * z * z - 1)),
    (4, -1, 0.669046544, lambda x, y, z: y * z * (7 * z * z - 3)),
    (4, 0, 0.105785547, lambda x, y, z: 35 * z ** 4 - 30 * z * z + 3),
    (4, 1, 0.669046544, lambda x, y, z: x * z * (7 * z * z - 3)),
    (4, 2, 0.473087348, lambda x, y, z: (x * x - y * y) * (7 * z * z - 1)),
    (4, 3, 1.770130770, lambda x, y, z: x * z * (x * x - 3 * y * y)),
    (4, 4, 0.625835735, lambda x, y, z: x ** 4 - 6 * x * x * y * y + y ** 4),
]
SH_COSINE_LOBE = [math.pi, 2 * math.pi / 3, math.pi / 4, 0.0, -math.pi / 24]  # A_0..A_4


def sh_order_of_basis(basis):
    """The SH order N of a manifest basis `sh2` or `sh:N` (N = 1..4); None for other bases."""
    if basis == "sh2":
        return 2
    if basis.startswith("sh:") and basis[3:] in ("1", "2", "3", "4"):
        return int(basis[3:])
    return None


def sh_basis_terms(manifest, s, n):
    """layout basis of an sh2 / sh:N volume: A_l L_j Y_j(n) for every j with A_l != 0, the
    texture of channel j found by its name sh_l<l>m<m> (m_neg<|m|> for m < 0)."""
    order = sh_order_of_basis(manifest["basis"])
    if order is None:
        raise ValueError("layout basis of basis %s is not checked (real SH only)" % manifest["basis"])
    x, y, z = n[:, 0], n[:, 1], n[:, 2]
    terms = []
    for l, m, constant, poly in SH_POLYNOMIALS:
        if l > order or SH_COSINE_LOBE[l] == 0.0:  # band 3: A_3 = 0, not read (docs/engine_layouts.md)
            continue
        name = "sh_l%dm%s%d" % (l, "_neg" if m < 0 else "", abs(m))
        terms.append(SH_COSINE_LOBE[l] * constant * s[name][:, :3] * poly(x, y, z)[:, None])
    return np.array(terms)


def lambert_contour(rel, n):
    """docs/engine_visibility.md: sum_i theta_i (n . gamma_i) over the loop (vertices relative to the
    receiver) clipped to dot(n, v) >= 0."""
    clipped = []
    m = len(rel)
    for i in range(m):
        a, b = rel[i], rel[(i + 1) % m]
        da, db = float(np.dot(n, a)), float(np.dot(n, b))
        if da >= 0:
            clipped.append(a)
        if (da >= 0) != (db >= 0):
            clipped.append(a + (b - a) * (da / (da - db)))
    total = 0.0
    for i in range(len(clipped)):
        a, b = clipped[i], clipped[(i + 1) % len(clipped)]
        g = np.cross(a, b)
        length = float(np.linalg.norm(g))
        if length > 0:
            total += math.atan2(length, float(np.dot(a, b))) * float(np.dot(n, g)) / length
    return total if len(clipped) >= 3 else 0.0


def exact_irradiance(light, x, n):
    """docs/engine_visibility.md / docs/format.md "Direct light": unshadowed irradiance, RGB."""
    kind = light["kind"]
    if kind == "directional":
        return np.array(light["irradiance"]) * max(0.0, -float(np.dot(n, light["direction"])))
    if kind in ("point", "spot"):
        d = np.array(light["position"]) - x
        d2 = float(np.dot(d, d))
        w = d / math.sqrt(d2)
        e = np.array(light["intensity"]) * max(0.0, float(np.dot(n, w))) / d2
        if kind == "spot":
            ci, co = math.cos(light["inner_cone"]), math.cos(light["outer_cone"])
            c = float(np.dot(light["direction"], -w))
            t = (1.0 if c > co else 0.0) if ci - co <= 1e-6 else min(1.0, max(0.0, (c - co) / (ci - co)))
            e = e * t * t
        return e
    total = 0.0
    for loop in light["loops"]:
        loop = np.array(loop)
        normal = np.array(light["normal"]) if kind == "polygon" else np.sum(
            np.cross(loop, np.roll(loop, -1, axis=0)), axis=0)
        side = float(np.dot(normal, x - loop[0]))
        sign = 1.0 if side > 0 else (-1.0 if side < 0 and light["two_sided"] else 0.0)
        if sign != 0.0:
            total += sign * lambert_contour(list(loop - x), n)
    return np.array(light["radiance"]) * max(0.0, -0.5 * total)


def strip_visibility(manifest, textures, x, light, index, component, ramp_of, filtered, weighted):
    """docs/shadow_visibility.md, "A second edge": where a corner of weight > 0 has a strip (far > 0),
    its own model of the strip at the point, the other corners the ramp of their own blended
    edge, plus every corner's residual; elsewhere `filtered` (the one-edge answer)."""
    idx, wt = weighted if weighted is not None else corner_weights(manifest, x)
    dims = np.array(manifest["dims"], dtype=np.int64)
    g = np.clip((x - np.array(manifest["bounds_min"])) / np.array(manifest["texel_spacing"]), 0.0,
                (dims - 1).astype(np.float64))
    group = light["visibility"]["texture"]
    at = lambda t, c: t[idx[c][:, 2], idx[c][:, 1], idx[c][:, 0]]
    strip, vtex = textures["light_edge_strip_%d" % index], textures[group]
    dtex = textures["light_edge_distance_" + group[len("light_visibility_"):]]
    wtex = textures["light_edge_width_" + group[len("light_visibility_"):]]
    out = filtered.copy()
    has = np.zeros(len(x), dtype=bool)
    for c in range(8):
        has |= (wt[c] != 0) & (at(strip, c)[:, 3] > 0)
    models, residual, others, dsum, wsum = (np.zeros(len(x)) for _ in range(5))
    for c in range(8):
        s, dc = at(strip, c), at(dtex, c)[:, component]
        wc, vc = at(wtex, c)[:, component], at(vtex, c)[:, component]
        residual += wt[c] * (vc - ramp_of(dc, wc))
        t = np.sum(s[:, :3] * (g - idx[c]), axis=1)
        sign = np.where(dc < 0, -1.0, 1.0)
        before = ramp_of(sign * (np.abs(dc) - t), wc)
        beyond = ramp_of(sign * (t - s[:, 3]), wc)
        model = np.where(sign > 0, np.maximum(before, beyond), np.minimum(before, beyond))
        own = s[:, 3] > 0
        models += np.where(own, wt[c] * model, 0.0)
        others += np.where(own, 0.0, wt[c])
        dsum += np.where(own, 0.0, wt[c] * dc)
        wsum += np.where(own, 0.0, wt[c] * wc)
    safe = np.maximum(others, 1e-30)
    models += np.where(others > 0, others * ramp_of(dsum / safe, wsum / safe), 0.0)
    out[has] = np.clip(models + residual, 0.0, 1.0)[has]
    return out


def direct_light(manifest, textures, x, n):
    """Occlusion exports: sum over listed lights of exact irradiance x sampled visibility; 0 otherwise."""
    direct = manifest.get("direct", {"mode": "baked"})
    out = np.zeros((len(x), 3))
    if direct["mode"] != "occlusion":
        return out
    uvw = x * np.array(manifest["uvw_scale"]) + np.array(manifest["uvw_bias"])
    # With exported depth moments the visibility is blended with the same weights as the SH.
    weighted = depth_weights(manifest, textures, x) if manifest.get("depth", {}).get("exported") else None
    for light in direct["lights"]:
        tex = textures[light["visibility"]["texture"]]
        sampled = sample_weighted(tex, *weighted) if weighted is not None else sample_trilinear(tex, uvw)
        component = "rgba".index(light["visibility"]["component"])
        vis = sampled[:, component]
        edges = direct.get("shadow_edges")
        if edges:  # docs/shadow_visibility.md: the edge's ramp plus the residual v - r
            group = light["visibility"]["texture"][len("light_visibility_"):]
            def part(name):
                t = textures["light_edge_" + name + "_" + group]
                return (sample_weighted(t, *weighted) if weighted is not None else sample_trilinear(t, uvw))[:, component]
            def ramp_of(d, w):
                return np.clip(0.5 + d / np.maximum(w, edges["min_width"]), 0.0, 1.0)
            d, w = part("distance"), part("width")
            if "light_edge_ramp_" + group in textures:
                r = part("ramp")
            else:  # the engine-size layouts: each corner's ramp from its own d and w, blended
                idx, wt = weighted if weighted is not None else corner_weights(manifest, x)
                dt, wdt = textures["light_edge_distance_" + group], textures["light_edge_width_" + group]
                r = sum(wt[c] * ramp_of(dt[idx[c][:, 2], idx[c][:, 1], idx[c][:, 0], component],
                                        wdt[idx[c][:, 2], idx[c][:, 1], idx[c][:, 0], component]) for c in range(8))
            vis = np.clip(ramp_of(d, w) + vis - r, 0.0, 1.0)
            strips = edges.get("strips")
            light_index = direct["lights"].index(light)
            if strips and "light_edge_strip_%d" % light_index in textures:
                vis = strip_visibility(manifest, textures, x, light, light_index, component, ramp_of, vis, weighted)
        for i in range(len(x)):
            out[i] += vis[i] * exact_irradiance(light, x[i], n[i])
    return out


def direction_to_square(d):
    """docs/format.md / manifest bins.bin_of_direction: hemisphere h and square point (u, v) of unit d."""
    h = (d[:, 2] < 0).astype(np.int64)
    inv = 1.0 / np.sqrt(1.0 + np.abs(d[:, 2]))
    px, py = d[:, 0] * inv, d[:, 1] * inv
    rho = np.hypot(px, py)
    phi = np.arctan2(py, px)
    phi = np.where(phi < -np.pi / 4, phi + 2 * np.pi, phi)
    q = np.pi / 4
    a = np.where(phi < q, rho, np.where(phi < 3 * q, -rho * (phi - np.pi / 2) / q,
                                         np.where(phi < 5 * q, -rho, rho * (phi - 3 * np.pi / 2) / q)))
    b = np.where(phi < q, rho * phi / q, np.where(phi < 3 * q, rho,
                                                  np.where(phi < 5 * q, -rho * (phi - np.pi) / q, -rho)))
    return h, np.clip(0.5 * (a + 1), 0, 1), np.clip(0.5 * (b + 1), 0, 1)


def check_compact_encoding(compact, vectors):
    """Every compact texel against section 4.2 applied to the texels of a float `vectors`
    export of the same volume: colour_c = |I_c|, dir = normalize(I_r + I_g + I_b).
    Returns the largest error relative to the direction's largest colour (and to 1 for dir)."""
    worst = 0.0
    for d in ("xpos", "xneg", "ypos", "yneg", "zpos", "zneg"):
        vec = [vectors["iv_%s_%s" % (d, c)][..., :3] for c in "rgb"]
        colour = np.stack([np.linalg.norm(v, axis=-1) for v in vec], axis=-1)
        total = vec[0] + vec[1] + vec[2]
        length = np.linalg.norm(total, axis=-1, keepdims=True)
        direction = np.where(length > 0, total / np.where(length > 0, length, 1.0), 0.0)
        scale = max(colour.max(), 1e-30)
        worst = max(worst, np.abs(compact["ivc_%s_colour" % d][..., :3] - colour).max() / scale)
        # Where the sum is tiny against the colours the direction is ill-conditioned: skip it.
        ok = (length[..., 0] > 1e-3 * scale)
        worst = max(worst, np.abs(compact["ivc_%s_dir" % d][..., :3] - direction)[ok].max(initial=0.0))
    return worst


def query(cli, volume, points, normals, extra=()):
    with tempfile.TemporaryDirectory() as tmp:
        csv = os.path.join(tmp, "points.csv")
        np.savetxt(csv, np.column_stack([points, normals]), delimiter=",", fmt="%.9g",
                   header="x,y,z,nx,ny,nz", comments="")
        out = os.path.join(tmp, "e.csv")
        subprocess.run([cli, "query", volume, "--raw", "--points", csv, "-o", out] + list(extra), check=True,
                       stderr=subprocess.DEVNULL)
        return np.loadtxt(out, delimiter=",", skiprows=1)[:, 6:9]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cli", required=True)
    ap.add_argument("--volume", required=True)
    ap.add_argument("--export", required=True)
    ap.add_argument("--points", type=int, default=500)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--vectors-export", help="for a compact export: a float `vectors` export of the same volume "
                    "and lattice; each compact texel must be its section 4.2 encoding")
    ap.add_argument("--tolerance", type=float, default=None,
                    help="the largest relative error accepted (default 1e-3 for half textures, 1e-5 for float)")
    ap.add_argument("--compact-tolerance", type=float, default=None,
                    help="for a compact export: the largest relative error against the query to accept "
                    "(the encoding is lossy; default: only report it)")
    args = ap.parse_args()

    with open(os.path.join(args.export, "manifest.json")) as f:
        manifest = json.load(f)
    if manifest["layout"] == "basis" and sh_order_of_basis(manifest.get("basis", "")) is None:
        print("layout basis of basis %s: not checked by this script (real SH only: sh2, sh:1..sh:4; "
              "export bins:R and moment:n volumes with --layout bins)" % manifest.get("basis"))
        return 2
    textures = load_textures(manifest, args.export)
    compact_sh = manifest["layout"] in COMPACT_SH_LAYOUTS
    if compact_sh:
        textures = decode_compact_sh(manifest, textures)
    rng = np.random.default_rng(args.seed)
    lo, hi = np.array(manifest["bounds_min"]), np.array(manifest["bounds_max"])
    # Points inside the box and a margin of 10% outside (clamp-to-edge must equal the query's clamp).
    margin = 0.1 * (hi - lo)
    x = (lo - margin) + rng.random((args.points, 3)) * (hi - lo + 2 * margin)
    x = x.astype(np.float32).astype(np.float64)  # the query reads float32 positions
    n = rng.normal(size=(args.points, 3))
    n /= np.linalg.norm(n, axis=1)[:, None]
    n = n.astype(np.float32).astype(np.float64)
    n /= np.linalg.norm(n, axis=1)[:, None]

    # Runtime volumes: the textures hold the indirect light, which the query gives with --indirect-only.
    extra = ["--indirect-only"] if manifest.get("direct", {}).get("mode") == "runtime" else []
    # An sh:N volume in an SH order-2 layout holds its bands 0..2: the query answers with those.
    if "truncated_from" in manifest:
        extra += ["--sh-order", "2"]
    moment = manifest["layout"] == "bins" and manifest["bins"]["basis"].startswith("moment:")
    # A moment volume is queried with the view vector (0, 0, 1) mirrored about n.
    d = n
    if moment:
        d = 2 * n[:, 2:3] * n - np.array([0.0, 0.0, 1.0])
        d /= np.linalg.norm(d, axis=1)[:, None]
    terms = irradiance_terms(manifest, textures, x, d)
    got = terms.sum(axis=0)
    if manifest["layout"] in ("sh1", "sh1-16"):
        # The order-1 part of E from the full query: the band-1 term is odd in n, so it is
        # (E(n) - E(-n)) / 2; the band-0 term is the mean over the six axis normals, where
        # the band-2 terms cancel.
        axes = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64)
        rows_x = np.repeat(x, 8, axis=0)
        rows_n = np.concatenate([np.vstack([n[i], -n[i], axes]) for i in range(len(n))])
        e = (query(args.cli, args.volume, rows_x, rows_n, extra) - direct_light(manifest, textures, rows_x, rows_n)).reshape(
            len(n), 8, 3)
        want = e[:, 2:, :].mean(axis=1) + 0.5 * (e[:, 0, :] - e[:, 1, :])
    else:
        want = query(args.cli, args.volume, x, n, (["--view", "0,0,1"] if moment else []) + extra)
        # Occlusion volumes: the query adds the listed lights' direct light, which the manifest's
        # formula (exact irradiance x visibility texture) must reproduce.
        want = want - direct_light(manifest, textures, x, n)

    tol = 1e-3 if manifest["component_type"] == "float16" else 1e-5
    if args.tolerance is not None:
        tol = args.tolerance
    status = 0
    if manifest["layout"] == "compact":
        if args.vectors_export:
            with open(os.path.join(args.vectors_export, "manifest.json")) as f:
                vmanifest = json.load(f)
            if vmanifest["layout"] != "vectors" or vmanifest["dims"] != manifest["dims"]:
                raise ValueError("--vectors-export is not a vectors export of the same lattice")
            enc = check_compact_encoding(textures, load_textures(vmanifest, args.vectors_export))
            print("compact encoding vs section 4.2 of the vectors texels: max relative error %.3g (tolerance %g)" % (
                enc, tol))
            if not enc <= tol:
                status = 1
        # The encoding is lossy: the error against the query is a figure, checked only if asked.
        tol = args.compact_tolerance if args.compact_tolerance is not None else float("inf")
    # Relative to the size of the terms that make up E around that point (sum of their
    # magnitudes, each with the largest of its 8 texels): rounding texels to half or float,
    # and the query's float position, scale with these, and where terms cancel (E close to 0
    # next to a bright light or a black node inside an object) no finite precision is
    # relative to E itself.
    # (The bins layout picks its texels by direction: its scale uses the same directions.)
    scale_dirs = d if manifest["layout"] == "bins" else np.abs(n)
    scale = np.abs(irradiance_terms(manifest, textures, x, scale_dirs, max_abs=True)).sum(axis=0)
    # The visibility texels are rounded like the others: their share scales with the direct light.
    scale = scale + np.abs(direct_light(manifest, textures, x, n))
    scale = np.maximum(scale, 1e-30)
    rel = np.abs(got - want) / scale
    if compact_sh:
        # The 8-bit rounding is the point of these layouts: each point must lie within the bound
        # it explains (plus the half-float tolerance of the other layouts), not within tol alone.
        bound = quantisation_bound(manifest, textures, x, n)
        excess = np.abs(got - want) / (bound + tol * scale)
        print("%s: %d points, |E - query| / (8-bit bound + %g x scale): max %.3g, mean %.3g; max |E - query| / bound %.3g" % (
            manifest["layout"], len(x), tol, excess.max(), excess.mean(), (np.abs(got - want) / np.maximum(bound, 1e-30)).max()))
        rel = excess * tol  # reported below in the usual units: tol x the share of the allowance used
    worst = int(np.argmax(rel.max(axis=1)))
    print("%s %s %s: %d points, max relative error %.3g (tolerance %g) at x=%s n=%s: got %s want %s" % (
        manifest["format"], manifest["layout"], manifest["component_type"], len(x), rel.max(), tol,
        np.round(x[worst], 4), np.round(n[worst], 4), got[worst], want[worst]))
    print("  relative error: p99 %.3g, share of points above 1e-3: %.2f %%" % (
        np.percentile(rel.max(axis=1), 99), 100.0 * np.mean(rel.max(axis=1) > 1e-3)))
    return status if rel.max() <= tol else 1


if __name__ == "__main__":
    sys.exit(main())
