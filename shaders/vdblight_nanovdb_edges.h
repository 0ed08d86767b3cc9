// vdblight_nanovdb_edges.h: a listed light's visibility from its shadow edges, read from the
// edge and strip arrays of a `--direct occlusion` volume's NanoVDB export (docs/engines.md,
// "NanoVDB"; the model of docs/shadow_visibility.md, as libvdblight/src/basis/shadow_edges.h
// and query/shared_cell.h evaluate it, operation for operation, so that the C build gives
// query's bits where it locates the point alike). Part of vdblight_nanovdb.h, which includes it
// after the cell locator.
//
// Per corner c of the point's level-0 cell and light i: v_c its stored visibility, (d_c, w_c)
// its nearest edge (signed distance and penumbra width, cells) and, where the volume has strips,
// (direction, far) its second edge. ramp(d, w) = clamp(0.5 + d / max(w, 1/16), 0, 1). In a
// cell none of whose corners (of weight > 0) has a strip:
//   clamp(ramp(sum wt_c d_c, sum wt_c w_c) + sum wt_c (v_c - ramp(d_c, w_c)), 0, 1);
// in the others each strip corner adds its own model of the strip at the point and the rest
// the ramp of their own blended edge (vdblight_nano_strip_visibility).
#ifndef VDBLIGHT_NANOVDB_EDGES_H
#define VDBLIGHT_NANOVDB_EDGES_H

#if defined(PNANOVDB_C)
#define VDBLIGHT_NANO_ABS(v) fabsf(v)
#else
#define VDBLIGHT_NANO_ABS(v) abs(v)
#endif

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

#endif  // VDBLIGHT_NANOVDB_EDGES_H
