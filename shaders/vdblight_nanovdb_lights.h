// vdblight_nanovdb_lights.h: the exact unshadowed irradiance of the lights a `--direct
// occlusion` volume lists, read from the light records of `vdblight_meta` (docs/engines.md,
// "NanoVDB"; the formulas of docs/format.md, "Direct light", as
// libvdblight/src/light/exact_irradiance.cpp evaluates them, here in float), and their
// visibility from the shadow edges (below). Part of vdblight_nanovdb.h, which includes it after
// the meta reader, the volume struct and the cell locator.
#ifndef VDBLIGHT_NANOVDB_LIGHTS_H
#define VDBLIGHT_NANOVDB_LIGHTS_H

#if defined(PNANOVDB_C)
#define VDBLIGHT_NANO_ABS(v) fabsf(v)
#else
#define VDBLIGHT_NANO_ABS(v) abs(v)
#endif

VDBLIGHT_NANO_FN float vdblight_nano_dot(pnanovdb_vec3_t a, pnanovdb_vec3_t b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
VDBLIGHT_NANO_FN pnanovdb_vec3_t vdblight_nano_cross(pnanovdb_vec3_t a, pnanovdb_vec3_t b) {
    pnanovdb_vec3_t c;
    c.x = a.y * b.z - a.z * b.y;
    c.y = a.z * b.x - a.x * b.z;
    c.z = a.x * b.y - a.y * b.x;
    return c;
}
VDBLIGHT_NANO_FN pnanovdb_vec3_t vdblight_nano_scale(pnanovdb_vec3_t a, float s) { return pnanovdb_vec3_mul(a, pnanovdb_vec3_uniform(s)); }

// Three meta values from index i (a light's vector, a loop vertex).
VDBLIGHT_NANO_FN pnanovdb_vec3_t vdblight_nano_meta3(pnanovdb_buf_t buf, pnanovdb_grid_handle_t meta, pnanovdb_int32_t i) {
    pnanovdb_vec3_t r;
    r.x = vdblight_nano_meta(buf, meta, i);
    r.y = vdblight_nano_meta(buf, meta, i + 1);
    r.z = vdblight_nano_meta(buf, meta, i + 2);
    return r;
}

// atan2(y, x) for y >= 0 (an edge's angle, 0..pi) from + - * / alone, as query's float path
// computes it (query/fast_exact_lights.cpp, atan2NonNegative: within 2e-7 relative): a GPU's
// atan is not (llvmpipe's cost the polygon light ~1e-4 of the irradiance). atan of
// t = min / max of (y, |x|); above tan(pi/8) of (t - 1) / (t + 1) plus pi/4, so that the
// polynomial u + u^3 P(u^2) only sees |u| <= tan(pi/8).
VDBLIGHT_NANO_FN float vdblight_nano_atan2_nonnegative(float y, float x) {
    float ax = VDBLIGHT_NANO_ABS(x);
    pnanovdb_bool_t swap = y > ax;
    float lo = swap ? ax : y, hi = swap ? y : ax;
    pnanovdb_bool_t upper = lo > 0.41421356f * hi;
    float num = upper ? lo - hi : lo, den = upper ? lo + hi : hi;
    float u = den > 0.0f ? num / den : 0.0f;
    float z = u * u;
    float p = ((0.080687128f * z - 0.138829082f) * z + 0.199782744f) * z - 0.333329678f;
    float a = u + u * z * p;
    if (upper) a += 0.785398163f;
    if (swap) a = 1.57079633f - a;
    if (x < 0.0f) a = 3.14159265f - a;
    return a;
}

// Lambert's term theta (n . gamma) of the edge a -> b (relative to the receiver).
VDBLIGHT_NANO_FN float vdblight_nano_edge(pnanovdb_vec3_t a, pnanovdb_vec3_t b, pnanovdb_vec3_t n) {
    pnanovdb_vec3_t c = vdblight_nano_cross(a, b);
    float len = VDBLIGHT_NANO_SQRT(vdblight_nano_dot(c, c));
    if (!(len > 0.0f)) return 0.0f;  // an edge pointing at the receiver subtends no angle
    return vdblight_nano_atan2_nonnegative(len, vdblight_nano_dot(a, b)) * vdblight_nano_dot(n, c) / len;
}

// Lambert's contour sum of the loop of `count` vertices from meta index `at`, relative to x,
// clipped to dot(n, v) >= 0 (Sutherland-Hodgman, streamed: each clipped vertex is met once).
VDBLIGHT_NANO_FN float vdblight_nano_contour(pnanovdb_buf_t buf, pnanovdb_grid_handle_t meta, pnanovdb_int32_t at,
                                             pnanovdb_int32_t count, pnanovdb_vec3_t x, pnanovdb_vec3_t n) {
    float sum = 0.0f;
    pnanovdb_int32_t m = 0;
    pnanovdb_vec3_t first = pnanovdb_vec3_uniform(0.0f), prev = first;
    for (pnanovdb_int32_t k = 0; k < count; ++k) {
        pnanovdb_vec3_t a = pnanovdb_vec3_sub(vdblight_nano_meta3(buf, meta, at + 3 * k), x);
        pnanovdb_vec3_t b = pnanovdb_vec3_sub(vdblight_nano_meta3(buf, meta, at + 3 * ((k + 1) % count)), x);
        float da = vdblight_nano_dot(n, a), db = vdblight_nano_dot(n, b);
        for (pnanovdb_int32_t e = 0; e < 2; ++e) {  // a if above, then the crossing if any
            pnanovdb_bool_t emit = e == 0 ? da >= 0.0f : (da >= 0.0f) != (db >= 0.0f);
            if (!emit) continue;
            pnanovdb_vec3_t p = e == 0 ? a : pnanovdb_vec3_add(a, vdblight_nano_scale(pnanovdb_vec3_sub(b, a), da / (da - db)));
            if (m == 0) first = p;
            else sum += vdblight_nano_edge(prev, p, n);
            prev = p;
            m += 1;
        }
    }
    if (m < 3) return 0.0f;
    return sum + vdblight_nano_edge(prev, first, n);
}

// +1 if x sees the front of the plane through p with normal nl, -1 its back (two-sided), else 0.
VDBLIGHT_NANO_FN float vdblight_nano_facing(pnanovdb_vec3_t nl, pnanovdb_vec3_t p, pnanovdb_bool_t two_sided, pnanovdb_vec3_t x) {
    float side = vdblight_nano_dot(nl, pnanovdb_vec3_sub(x, p));
    if (side > 0.0f) return 1.0f;
    if (side < 0.0f && two_sided) return -1.0f;
    return 0.0f;
}

// Exact unshadowed irradiance at x (unit normal n) of listed light i (docs/format.md, "Direct light").
VDBLIGHT_NANO_FN pnanovdb_vec3_t vdblight_nano_light_irradiance(pnanovdb_buf_t buf, PNANOVDB_IN(vdblight_nano_volume_t) v,
                                                                pnanovdb_int32_t i, pnanovdb_vec3_t x, pnanovdb_vec3_t n) {
    pnanovdb_grid_handle_t meta = PNANOVDB_DEREF(v).meta;
    pnanovdb_int32_t r = VDBLIGHT_NANO_META_LIGHTS + VDBLIGHT_NANO_LIGHT_FLOATS * i;
    pnanovdb_int32_t kind = pnanovdb_float_to_int32(vdblight_nano_meta(buf, meta, r));
    pnanovdb_bool_t two_sided = vdblight_nano_meta(buf, meta, r + 1) != 0.0f;
    pnanovdb_vec3_t value = vdblight_nano_meta3(buf, meta, r + 2);
    pnanovdb_vec3_t position = vdblight_nano_meta3(buf, meta, r + 5);
    pnanovdb_vec3_t direction = vdblight_nano_meta3(buf, meta, r + 8);
    pnanovdb_vec3_t zero = pnanovdb_vec3_uniform(0.0f);
    // n as given where it is unit within float rounding, else normalised: query's float path
    // takes the same n (query/fast_exact_lights.h, floatPathNormal), whose last bit moves a
    // polygon seen as a sliver of the hemisphere by ~1e-4 of its light.
    float squared = vdblight_nano_dot(n, n);
    if (VDBLIGHT_NANO_ABS(1.0f - squared) > 1e-6f) n = vdblight_nano_scale(n, 1.0f / VDBLIGHT_NANO_SQRT(squared));
    if (kind == 2) {  // directional: E cos
        float c = -vdblight_nano_dot(n, direction);
        return c > 0.0f ? vdblight_nano_scale(value, c) : zero;
    }
    if (kind < 2) {  // point, spot: I cos / d^2 (times the spot's falloff t^2)
        pnanovdb_vec3_t d = pnanovdb_vec3_sub(position, x);
        float dist2 = vdblight_nano_dot(d, d);
        if (!(dist2 > 0.0f)) return zero;
        pnanovdb_vec3_t w = vdblight_nano_scale(d, 1.0f / VDBLIGHT_NANO_SQRT(dist2));
        float c = vdblight_nano_dot(n, w);
        if (!(c > 0.0f)) return zero;
        float falloff = 1.0f;
        if (kind == 1) {
            float cos_inner = vdblight_nano_meta(buf, meta, r + 11), cos_outer = vdblight_nano_meta(buf, meta, r + 12);
            float ca = -vdblight_nano_dot(direction, w);
            if (ca <= cos_outer) return zero;
            if (cos_inner - cos_outer > 1e-6f) {
                float t = (ca - cos_outer) / (cos_inner - cos_outer);
                if (t > 1.0f) t = 1.0f;
                falloff = t * t;
            }
        }
        return vdblight_nano_scale(value, c * falloff / dist2);
    }
    // polygon, mesh: Lambert's formula over each loop clipped to the hemisphere of n, counted
    // where x sees the emitting side (one plane for a polygon, each triangle's own for a mesh).
    pnanovdb_vec3_t normal = vdblight_nano_meta3(buf, meta, r + 13);
    pnanovdb_int32_t at = pnanovdb_float_to_int32(vdblight_nano_meta(buf, meta, r + 16));
    pnanovdb_int32_t loops = pnanovdb_float_to_int32(vdblight_nano_meta(buf, meta, r + 17));
    float polygon_side = 0.0f;
    if (kind == 3 && loops > 0) polygon_side = vdblight_nano_facing(normal, vdblight_nano_meta3(buf, meta, at + 1), two_sided, x);
    float sum = 0.0f;
    for (pnanovdb_int32_t l = 0; l < loops; ++l) {
        pnanovdb_int32_t count = pnanovdb_float_to_int32(vdblight_nano_meta(buf, meta, at));
        float side = polygon_side;
        if (kind == 4 && count > 0) {  // the triangle's own normal (Newell's vector)
            pnanovdb_vec3_t newell = zero;
            for (pnanovdb_int32_t k = 0; k < count; ++k)
                newell = pnanovdb_vec3_add(newell, vdblight_nano_cross(vdblight_nano_meta3(buf, meta, at + 1 + 3 * k),
                                                                      vdblight_nano_meta3(buf, meta, at + 1 + 3 * ((k + 1) % count))));
            side = vdblight_nano_facing(newell, vdblight_nano_meta3(buf, meta, at + 1), two_sided, x);
        }
        if (side != 0.0f && count > 0) sum += side * vdblight_nano_contour(buf, meta, at + 1, count, x, n);
        at += 1 + 3 * count;
    }
    float e = -0.5f * sum;
    return e > 0.0f ? vdblight_nano_scale(value, e) : zero;
}

// ---------------------------------------------------------------------------------------------
// A listed light's visibility from its shadow edges, read from the edge and strip arrays of the
// export (docs/engines.md, "NanoVDB"; the model of docs/shadow_visibility.md, as
// libvdblight/src/basis/shadow_edges.h and query/shared_cell.h evaluate it, operation for
// operation, so that the C build gives query's bits where it locates the point alike).
//
// Per corner c of the point's level-0 cell and light i: v_c its stored visibility, (d_c, w_c)
// its nearest edge (signed distance and penumbra width, cells) and, where the volume has strips,
// (direction, far) its second edge. ramp(d, w) = clamp(0.5 + d / max(w, 1/16), 0, 1). In a
// cell none of whose corners (of weight > 0) has a strip:
//   clamp(ramp(sum wt_c d_c, sum wt_c w_c) + sum wt_c (v_c - ramp(d_c, w_c)), 0, 1);
// in the others each strip corner adds its own model of the strip at the point and the rest
// the ramp of their own blended edge (vdblight_nano_strip_visibility).

// shadow_edge::kMinWidth: a hard edge to within 1/16 of a cell.
#define VDBLIGHT_NANO_MIN_EDGE_WIDTH 0.0625f

// shadow_edge::ramp, with std::max and std::clamp's comparisons.
VDBLIGHT_NANO_FN float vdblight_nano_edge_ramp(float d, float w) {
    float r = 0.5f + d / (w < VDBLIGHT_NANO_MIN_EDGE_WIDTH ? VDBLIGHT_NANO_MIN_EDGE_WIDTH : w);
    return r < 0.0f ? 0.0f : (1.0f < r ? 1.0f : r);
}

VDBLIGHT_NANO_FN float vdblight_nano_clamp01(float r) { return r < 0.0f ? 0.0f : (1.0f < r ? 1.0f : r); }

// Float `k` (0..3) of node `node`'s record in the per-light array starting at `a` whose records
// are `size` bytes.
VDBLIGHT_NANO_FN float vdblight_nano_edge_read(pnanovdb_buf_t buf, pnanovdb_address_t a, pnanovdb_uint32_t size,
                                               pnanovdb_uint32_t node, pnanovdb_uint32_t k) {
    return pnanovdb_read_float(buf, pnanovdb_address_offset(pnanovdb_address_offset_product(a, size, node), 4u * k));
}

// The offset (cells) of world point x from level-0 node ijk along one axis: `u` the point's
// index coordinate as located, `c` the same clamped into the nodes' box (NaN to the first node)
// and `near` the offset measured from the node's own world position. Inside the box it is
// `near`: (x - node) / spacing loses less to float rounding than u - i does (query works in
// double here, shared_cell.h, offsetFromNode); outside, the clamped coordinate's offset.
VDBLIGHT_NANO_FN float vdblight_nano_axis_offset(float u, float c, float near, pnanovdb_int32_t i) {
    return u == c ? near : c - pnanovdb_int32_to_float(i);
}

// The offset (cells) of coordinate x from node i along `axis`, from level 0's exact frame at
// meta index `frame` (vdblight/export/engines.h, nanovdb_meta::kFrame): x - origin as the
// unevaluated sum hi + lo of two floats (Knuth's two-sum), minus i times the spacing in three
// parts of which the first two give exact products, so that what is left is rounded to the
// offset's own magnitude (a cell or two) rather than to x's, before it is scaled by 1 / spacing.
// query measures the offset in double (shared_cell.h, offsetFromNode); the grid's float map
// (origin + i spacing rounded, then subtracted) was off by up to about 1e-6 cell, which the
// edges' ramp (up to 16 per cell) turned into up to 4e-5 of the irradiance.
VDBLIGHT_NANO_FN float vdblight_nano_frame_offset(pnanovdb_buf_t buf, pnanovdb_grid_handle_t meta, pnanovdb_int32_t frame,
                                                  pnanovdb_int32_t axis, float x, pnanovdb_int32_t i) {
    float origin_hi = vdblight_nano_meta(buf, meta, frame + axis), origin_lo = vdblight_nano_meta(buf, meta, frame + 3 + axis);
    float s1 = vdblight_nano_meta(buf, meta, frame + 6), s2 = vdblight_nano_meta(buf, meta, frame + 7);
    float s3 = vdblight_nano_meta(buf, meta, frame + 8), inv = vdblight_nano_meta(buf, meta, frame + 9);
    float fi = pnanovdb_int32_to_float(i);
    VDBLIGHT_NANO_PRECISE float hi = x - origin_hi;
    VDBLIGHT_NANO_PRECISE float back = hi - x;
    VDBLIGHT_NANO_PRECISE float lo = (x - (hi - back)) + (-origin_hi - back);
    VDBLIGHT_NANO_PRECISE float r = (hi - fi * s1) - fi * s2;
    VDBLIGHT_NANO_PRECISE float rest = (lo - origin_lo) - fi * s3;
    return (r + rest) * inv;
}

// The offsets (cells) of world point x from level-0 node ijk, x clamped into the nodes' box as
// query clamps it for the edges.
VDBLIGHT_NANO_FN pnanovdb_vec3_t vdblight_nano_node_offset(pnanovdb_buf_t buf, PNANOVDB_IN(vdblight_nano_volume_t) v,
                                                          pnanovdb_vec3_t x, pnanovdb_coord_t ijk) {
    pnanovdb_grid_handle_t g = PNANOVDB_DEREF(v).first[0];
    pnanovdb_vec3_t u = pnanovdb_grid_world_to_indexf(buf, g, PNANOVDB_REF(x));
    pnanovdb_vec3_t c = u;
    if (!(c.x > 0.0f)) c.x = 0.0f;
    if (!(c.y > 0.0f)) c.y = 0.0f;
    if (!(c.z > 0.0f)) c.z = 0.0f;
    float hx = pnanovdb_int32_to_float(PNANOVDB_DEREF(v).dims_x - 1), hy = pnanovdb_int32_to_float(PNANOVDB_DEREF(v).dims_y - 1),
          hz = pnanovdb_int32_to_float(PNANOVDB_DEREF(v).dims_z - 1);
    if (hx < c.x) c.x = hx;
    if (hy < c.y) c.y = hy;
    if (hz < c.z) c.z = hz;
    pnanovdb_vec3_t node;
    node.x = pnanovdb_int32_to_float(ijk.x);
    node.y = pnanovdb_int32_to_float(ijk.y);
    node.z = pnanovdb_int32_to_float(ijk.z);
    pnanovdb_vec3_t d = pnanovdb_vec3_sub(x, pnanovdb_grid_index_to_worldf(buf, g, PNANOVDB_REF(node)));
    pnanovdb_vec3_t near = pnanovdb_grid_world_to_index_dirf(buf, g, PNANOVDB_REF(d));
    pnanovdb_int32_t frame = PNANOVDB_DEREF(v).frame;
    if (frame > 0) {  // files with the exact frame (older ones: the grid's float map above)
        near.x = vdblight_nano_frame_offset(buf, PNANOVDB_DEREF(v).meta, frame, 0, x.x, ijk.x);
        near.y = vdblight_nano_frame_offset(buf, PNANOVDB_DEREF(v).meta, frame, 1, x.y, ijk.y);
        near.z = vdblight_nano_frame_offset(buf, PNANOVDB_DEREF(v).meta, frame, 2, x.z, ijk.z);
    }
    pnanovdb_vec3_t o;
    o.x = vdblight_nano_axis_offset(u.x, c.x, near.x, ijk.x);
    o.y = vdblight_nano_axis_offset(u.y, c.y, near.y, ijk.y);
    o.z = vdblight_nano_axis_offset(u.z, c.z, near.z, ijk.z);
    return o;
}

// A corner's own picture of the strip at offset (ox, oy, oz) cells from it (shadow_edge::cornerModel):
// the node's side of its nearest edge (d, w) extended as a plane across the cell (normal
// (dx, dy, dz)), and past the strip's far side (`far_side` cells) its side again. A lit node sees a thin shadow, a shadowed one a lit gap.
VDBLIGHT_NANO_FN float vdblight_nano_strip_model(float d, float w, float dx, float dy, float dz, float far_side,
                                                 float ox, float oy, float oz) {
    float t = dx * ox + dy * oy + dz * oz;
    float side = d < 0.0f ? -1.0f : 1.0f;
    float before = vdblight_nano_edge_ramp(side * (VDBLIGHT_NANO_ABS(d) - t), w);
    if (!(far_side > 0.0f)) return before;
    float beyond = vdblight_nano_edge_ramp(side * (t - far_side), w);
    if (side > 0.0f) return before < beyond ? beyond : before;
    return beyond < before ? beyond : before;
}

// Light i's visibility in a strip's cell (shadow_edge::visibility with the corners' full edges):
// the strip corners' models, the other corners' ramp of their own blended edge (renormalised
// over them), and every corner's residual v_c - model_c(node).
VDBLIGHT_NANO_FN float vdblight_nano_strip_visibility(pnanovdb_buf_t buf, PNANOVDB_IN(vdblight_nano_volume_t) v,
                                                      PNANOVDB_IN(vdblight_nano_cell_t) cell, pnanovdb_uint32_t node[8],
                                                      pnanovdb_vec3_t x, pnanovdb_int32_t i) {
    pnanovdb_uint32_t n4 = PNANOVDB_DEREF(v).visibility_stride;  // 4 bytes x nodes
    pnanovdb_uint32_t li = pnanovdb_int32_as_uint32(i);
    pnanovdb_address_t vis = pnanovdb_address_offset_product(PNANOVDB_DEREF(v).visibility0, n4, li);
    pnanovdb_address_t dist = pnanovdb_address_offset_product(PNANOVDB_DEREF(v).edges0, n4, 2u * li);
    pnanovdb_address_t width = pnanovdb_address_offset_product(dist, n4, 1u);
    pnanovdb_address_t strip = pnanovdb_address_offset_product(PNANOVDB_DEREF(v).strips0, 4u * n4, li);
    float models = 0.0f, residual = 0.0f, others = 0.0f, d = 0.0f, w = 0.0f;
    for (pnanovdb_int32_t c = 0; c < 8; ++c) {
        float wt = PNANOVDB_DEREF(cell).w[c];
        if (wt == 0.0f) continue;
        float dc = vdblight_nano_edge_read(buf, dist, 4u, node[c], 0u), wc = vdblight_nano_edge_read(buf, width, 4u, node[c], 0u);
        float sx = vdblight_nano_edge_read(buf, strip, 16u, node[c], 0u), sy = vdblight_nano_edge_read(buf, strip, 16u, node[c], 1u),
              sz = vdblight_nano_edge_read(buf, strip, 16u, node[c], 2u);
        float far_side = vdblight_nano_edge_read(buf, strip, 16u, node[c], 3u);
        float own = vdblight_nano_strip_model(dc, wc, sx, sy, sz, far_side, 0.0f, 0.0f, 0.0f);
        residual += wt * (vdblight_nano_edge_read(buf, vis, 4u, node[c], 0u) - own);
        if (far_side > 0.0f) {
            pnanovdb_vec3_t o = vdblight_nano_node_offset(buf, v, x, vdblight_nano_corner(cell, c));
            models += wt * vdblight_nano_strip_model(dc, wc, sx, sy, sz, far_side, o.x, o.y, o.z);
        } else {
            others += wt;
            d += wt * dc;
            w += wt * wc;
        }
    }
    if (others > 0.0f) models += others * vdblight_nano_edge_ramp(d / others, w / others);
    return vdblight_nano_clamp01(models + residual);
}

// Light i's visibility at x from its shadow edges, with the cell's weights and its corners'
// node indices `node` (level 0: occlusion volumes have one level).
VDBLIGHT_NANO_FN float vdblight_nano_edge_visibility(pnanovdb_buf_t buf, PNANOVDB_IN(vdblight_nano_volume_t) v,
                                                     PNANOVDB_IN(vdblight_nano_cell_t) cell, pnanovdb_uint32_t node[8],
                                                     pnanovdb_vec3_t x, pnanovdb_int32_t i) {
    pnanovdb_uint32_t n4 = PNANOVDB_DEREF(v).visibility_stride;
    pnanovdb_uint32_t li = pnanovdb_int32_as_uint32(i);
    if (PNANOVDB_DEREF(v).shadow_edges > 1) {
        pnanovdb_address_t strip = pnanovdb_address_offset_product(PNANOVDB_DEREF(v).strips0, 4u * n4, li);
        pnanovdb_bool_t has_strip = PNANOVDB_FALSE;
        for (pnanovdb_int32_t c = 0; c < 8; ++c)
            has_strip = has_strip || (PNANOVDB_DEREF(cell).w[c] != 0.0f && vdblight_nano_edge_read(buf, strip, 16u, node[c], 3u) > 0.0f);
        if (has_strip) return vdblight_nano_strip_visibility(buf, v, cell, node, x, i);
    }
    pnanovdb_address_t vis = pnanovdb_address_offset_product(PNANOVDB_DEREF(v).visibility0, n4, li);
    pnanovdb_address_t dist = pnanovdb_address_offset_product(PNANOVDB_DEREF(v).edges0, n4, 2u * li);
    pnanovdb_address_t width = pnanovdb_address_offset_product(dist, n4, 1u);
    float d = 0.0f, w = 0.0f, residual = 0.0f;
    for (pnanovdb_int32_t c = 0; c < 8; ++c) {
        float wt = PNANOVDB_DEREF(cell).w[c];
        if (wt == 0.0f) continue;
        float dc = vdblight_nano_edge_read(buf, dist, 4u, node[c], 0u), wc = vdblight_nano_edge_read(buf, width, 4u, node[c], 0u);
        d += wt * dc;
        w += wt * wc;
        residual += wt * (vdblight_nano_edge_read(buf, vis, 4u, node[c], 0u) - vdblight_nano_edge_ramp(dc, wc));
    }
    return vdblight_nano_clamp01(vdblight_nano_edge_ramp(d, w) + residual);
}

#endif  // VDBLIGHT_NANOVDB_LIGHTS_H
