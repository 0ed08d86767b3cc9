// vdblight_nanovdb.h: irradiance from a vdblight NanoVDB export (`vdblight export VOLUME
// -o out.nvdb --format nanovdb`), written on PNanoVDB.h so that the same source compiles as C
// (PNANOVDB_C), GLSL (PNANOVDB_GLSL) and HLSL (PNANOVDB_HLSL). Include PNanoVDB.h first (in
// GLSL after declaring `pnanovdb_buf_data[]`, the buffer of the file's grids); docs/engines.md,
// "NanoVDB", shows a complete GLSL compute shader.
//
// The buffer holds the grid buffers of the .nvdb back to back in file order, starting with
// `vdblight_meta` at byte 0 (what nanovdb::io::readGrids returns, concatenated). Then
//
//   vdblight_nano_volume_t v = vdblight_nano_open(buf);            // once: finds the grids
//   pnanovdb_vec3_t e = vdblight_nano_irradiance(buf, v, x, n);   // per point x, unit normal n
//
// gives what `vdblight query` gives (irradiance, W/m^2 per colour) for volumes of basis sh:N
// (N = 1..4; the default bake's sh:4) and sh2, uniform or multi-level (bilevel, adaptive):
// - x clamped into level 0's node box, then down the refined cells (`refined_L<k>` masks) to
//   the finest level whose cell holds x (docs/format.md, "Levels");
// - trilinear over the cell's eight nodes, the weights multiplied by each corner's
//   visibility from the depth moments in cells of the finest level when the volume has them,
//   and renormalised (docs/format.md, "Depth moments");
// - E = sum over coefficients j of A_l(j) Y_j(n) L_j (the clamped-cosine constants A_0..A_4 =
//   pi, 2 pi / 3, pi / 4, 0, -pi / 24).
// - `--direct occlusion` volumes: plus, for each listed light, its exact unshadowed irradiance
//   (point, spot, directional, polygon and mesh lights; docs/engines.md, "Direct light") times
//   its visibility interpolated with the same weights, or, where the file has shadow edges,
//   the edge model of query with those weights (vdblight_nanovdb_lights.h).
// Culled volumes (`--cull-solids`) and other bases are not looked up (vdblight_nano_open sets
// `supported` to false). Everything is float: volumes far from the origin lose precision here
// where `query` works in double.
//
// Why it can be fast and small: each level is one tree (`vdblight_nodes`, a UInt32 grid whose
// value is the node's index) and its channels are arrays in that grid's blind data, channel-
// major, so the lookup walks the tree once per corner and reads every channel of the node at
// a fixed stride from the first.
#ifndef VDBLIGHT_NANOVDB_H
#define VDBLIGHT_NANOVDB_H

#ifndef VDBLIGHT_NANO_MAX_LEVELS
#define VDBLIGHT_NANO_MAX_LEVELS 8
#endif

// `precise` keeps a GLSL or HLSL compiler from reassociating or fusing the operations of an
// error-free sum (vdblight_nanovdb_lights.h, vdblight_nano_frame_offset); C does neither.
#if defined(PNANOVDB_C)
#include <math.h>
#define VDBLIGHT_NANO_PRECISE
#define VDBLIGHT_NANO_FN static
#define VDBLIGHT_NANO_SQRT(v) sqrtf(v)
#elif defined(PNANOVDB_HLSL)
#define VDBLIGHT_NANO_PRECISE precise
#define VDBLIGHT_NANO_FN
#define VDBLIGHT_NANO_SQRT(v) sqrt(v)
#else
#define VDBLIGHT_NANO_PRECISE precise
#define VDBLIGHT_NANO_FN
#define VDBLIGHT_NANO_SQRT(v) sqrt(v)
#endif

// The numbers in voxels (i, 0, 0) of `vdblight_meta` (vdblight/export_nanovdb.h).
#define VDBLIGHT_NANO_META_SH_ORDER 1
#define VDBLIGHT_NANO_META_CHANNELS 2
#define VDBLIGHT_NANO_META_LEVELS 3
#define VDBLIGHT_NANO_META_REFINE 4
#define VDBLIGHT_NANO_META_DEPTH 5
#define VDBLIGHT_NANO_META_VISIBILITY 8
#define VDBLIGHT_NANO_META_VALIDITY 9
#define VDBLIGHT_NANO_META_DIMS 10
#define VDBLIGHT_NANO_META_SH_KIND 13
#define VDBLIGHT_NANO_META_SHADOW_EDGES 14
#define VDBLIGHT_NANO_META_FRAME 15    // where level 0's exact frame starts (0: a file without it)
#define VDBLIGHT_NANO_META_DIRECT_MODE 6
#define VDBLIGHT_NANO_META_LIGHTS 16   // light i's record of 20 numbers at 16 + 20 i
#define VDBLIGHT_NANO_LIGHT_FLOATS 20

struct vdblight_nano_volume_t {
    pnanovdb_bool_t supported;  // a volume this lookup reads (sh2 or sh:1..4, dense level 0)
    pnanovdb_int32_t sh_order, channels, levels, refine, depth, visibility;
    pnanovdb_int32_t direct_mode;  // 0 baked, 1 runtime, 2 occlusion
    pnanovdb_int32_t folded;  // basis sh2: A_l applied to the coefficients before interpolating (its lookup's bits)
    pnanovdb_int32_t dims_x, dims_y, dims_z;  // level 0's nodes per axis
    pnanovdb_grid_handle_t first[VDBLIGHT_NANO_MAX_LEVELS];    // each level's vdblight_nodes grid
    pnanovdb_address_t channels0[VDBLIGHT_NANO_MAX_LEVELS];    // its channel arrays (blind data): channel 0, node 0
    pnanovdb_grid_handle_t refined[VDBLIGHT_NANO_MAX_LEVELS];  // refined_L<k> (k < levels - 1): float, active = refined
    pnanovdb_uint32_t stride[VDBLIGHT_NANO_MAX_LEVELS];        // bytes from a channel's array to the next (12 x nodes)
    pnanovdb_grid_handle_t meta;                               // vdblight_meta (lights)
    pnanovdb_address_t visibility0;                            // level 0's visibility of light 0, node 0 (occlusion)
    pnanovdb_uint32_t visibility_stride;                       // bytes from a light's array to the next (4 x nodes)
    pnanovdb_int32_t shadow_edges;                             // 0 none, 1 nearest edges, 2 and strips
    pnanovdb_address_t edges0;                                 // light 0's edge distances, node 0 (then its widths)
    pnanovdb_address_t strips0;                                // light 0's strips (direction xyz, far), node 0
    pnanovdb_int32_t frame;                                    // meta index of level 0's exact frame, 0 if none
};
PNANOVDB_STRUCT_TYPEDEF(vdblight_nano_volume_t)

// The cell a lookup interpolates in: its level, lower corner (index space of that level) and
// the corners' weights (corner c: x offset c & 1, y (c >> 1) & 1, z c >> 2).
struct vdblight_nano_cell_t {
    pnanovdb_int32_t level;
    pnanovdb_coord_t lo;
    pnanovdb_int32_t step_x, step_y, step_z;  // 0 along an axis of level 0 with a single node
    float f[3];
    float w[8];
};
PNANOVDB_STRUCT_TYPEDEF(vdblight_nano_cell_t)

VDBLIGHT_NANO_FN float vdblight_nano_meta(pnanovdb_buf_t buf, pnanovdb_grid_handle_t meta, pnanovdb_int32_t i) {
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(PNANOVDB_REF(acc), pnanovdb_tree_get_root(buf, pnanovdb_grid_get_tree(buf, meta)));
    pnanovdb_coord_t ijk;
    ijk.x = i;
    ijk.y = 0;
    ijk.z = 0;
    return pnanovdb_read_float(buf, pnanovdb_readaccessor_get_value_address(PNANOVDB_GRID_TYPE_FLOAT, buf, PNANOVDB_REF(acc), PNANOVDB_REF(ijk)));
}

VDBLIGHT_NANO_FN pnanovdb_grid_handle_t vdblight_nano_next(pnanovdb_buf_t buf, pnanovdb_grid_handle_t g, pnanovdb_uint32_t count) {
    pnanovdb_uint32_t size = pnanovdb_uint64_low(pnanovdb_grid_get_grid_size(buf, g));
    pnanovdb_grid_handle_t next;
    next.address = pnanovdb_address_offset_product(g.address, size, count);
    return next;
}

// Reads the meta grid and walks the grids in the export's order: per level its channels,
// depth grids, refined mask and validity grid, then (after level 0's) the visibility grids.
VDBLIGHT_NANO_FN vdblight_nano_volume_t vdblight_nano_open(pnanovdb_buf_t buf) {
    vdblight_nano_volume_t v;
    pnanovdb_grid_handle_t g;
    g.address = pnanovdb_address_null();
    v.sh_order = pnanovdb_float_to_int32(vdblight_nano_meta(buf, g, VDBLIGHT_NANO_META_SH_ORDER));
    v.channels = pnanovdb_float_to_int32(vdblight_nano_meta(buf, g, VDBLIGHT_NANO_META_CHANNELS));
    v.levels = pnanovdb_float_to_int32(vdblight_nano_meta(buf, g, VDBLIGHT_NANO_META_LEVELS));
    v.refine = pnanovdb_float_to_int32(vdblight_nano_meta(buf, g, VDBLIGHT_NANO_META_REFINE));
    v.depth = pnanovdb_float_to_int32(vdblight_nano_meta(buf, g, VDBLIGHT_NANO_META_DEPTH));
    v.visibility = pnanovdb_float_to_int32(vdblight_nano_meta(buf, g, VDBLIGHT_NANO_META_VISIBILITY));
    pnanovdb_int32_t validity = pnanovdb_float_to_int32(vdblight_nano_meta(buf, g, VDBLIGHT_NANO_META_VALIDITY));
    v.direct_mode = pnanovdb_float_to_int32(vdblight_nano_meta(buf, g, VDBLIGHT_NANO_META_DIRECT_MODE));
    v.folded = pnanovdb_float_to_int32(vdblight_nano_meta(buf, g, VDBLIGHT_NANO_META_SH_KIND));
    v.dims_x = pnanovdb_float_to_int32(vdblight_nano_meta(buf, g, VDBLIGHT_NANO_META_DIMS));
    v.dims_y = pnanovdb_float_to_int32(vdblight_nano_meta(buf, g, VDBLIGHT_NANO_META_DIMS + 1));
    v.dims_z = pnanovdb_float_to_int32(vdblight_nano_meta(buf, g, VDBLIGHT_NANO_META_DIMS + 2));
    pnanovdb_int32_t version = pnanovdb_float_to_int32(vdblight_nano_meta(buf, g, 0));
    v.supported = version == 2 && v.sh_order >= 1 && v.sh_order <= 4 && v.channels == (v.sh_order + 1) * (v.sh_order + 1) &&
                  v.levels >= 1 && v.levels <= VDBLIGHT_NANO_MAX_LEVELS &&
                  pnanovdb_grid_get_grid_type(buf, vdblight_nano_next(buf, g, 1u)) == PNANOVDB_GRID_TYPE_UINT32;
    v.meta = g;
    g = vdblight_nano_next(buf, g, 1u);
    v.visibility0 = g.address;
    v.visibility_stride = 0u;
    v.shadow_edges = pnanovdb_float_to_int32(vdblight_nano_meta(buf, v.meta, VDBLIGHT_NANO_META_SHADOW_EDGES));
    if (v.visibility <= 0) v.shadow_edges = 0;
    v.frame = pnanovdb_float_to_int32(vdblight_nano_meta(buf, v.meta, VDBLIGHT_NANO_META_FRAME));
    v.edges0 = g.address;
    v.strips0 = g.address;
    for (pnanovdb_int32_t l = 0; l < VDBLIGHT_NANO_MAX_LEVELS; ++l) {
        v.first[l] = g;
        v.channels0[l] = g.address;
        v.refined[l] = g;
        v.stride[l] = 0u;
        if (l >= v.levels || !v.supported) continue;
        // The blind data starts byte_offset bytes after its record (NanoVDB's GridBlindMetaData).
        pnanovdb_gridblindmetadata_handle_t blind = pnanovdb_grid_get_gridblindmetadata(buf, g, 0u);
        v.channels0[l] = pnanovdb_address_offset64(blind.address, pnanovdb_int64_as_uint64(pnanovdb_gridblindmetadata_get_byte_offset(buf, blind)));
        pnanovdb_uint32_t nodes = pnanovdb_uint64_low(pnanovdb_tree_get_voxel_count(buf, pnanovdb_grid_get_tree(buf, g)));
        v.stride[l] = 12u * nodes;
        if (l == 0 && v.visibility > 0) {
            pnanovdb_uint32_t arrays = pnanovdb_int32_as_uint32(v.channels + (v.depth != 0 ? 4 : 0));
            v.visibility0 = pnanovdb_address_offset_product(v.channels0[0], v.stride[0], arrays);
            v.visibility_stride = 4u * nodes;
            // After the visibility: per light N distances and N widths, then per light N strips.
            pnanovdb_uint32_t lights = pnanovdb_int32_as_uint32(v.visibility);
            v.edges0 = pnanovdb_address_offset_product(v.visibility0, v.visibility_stride, lights);
            v.strips0 = pnanovdb_address_offset_product(v.edges0, v.visibility_stride, 2u * lights);
        }
        g = vdblight_nano_next(buf, g, 1u);
        v.refined[l] = g;
        if (l + 1 < v.levels) g = vdblight_nano_next(buf, g, 1u);
        if (validity != 0) g = vdblight_nano_next(buf, g, 1u);
    }
    return v;
}

// Lattice coordinate u along an axis of n >= 2 nodes, clamped into [0, n - 1] (NaN to 0):
// the lower node of its cell and the fraction in it.
VDBLIGHT_NANO_FN pnanovdb_int32_t vdblight_nano_split(float u, pnanovdb_int32_t n, PNANOVDB_INOUT(float) f) {
    if (!(u >= 0.0f)) u = 0.0f;
    if (u > pnanovdb_int32_to_float(n - 1)) u = pnanovdb_int32_to_float(n - 1);
    pnanovdb_int32_t i = pnanovdb_float_to_int32(u);
    if (i > n - 2) i = n - 2;
    PNANOVDB_DEREF(f) = u - pnanovdb_int32_to_float(i);
    return i;
}

// A fraction f of a refined cell split into K sub-cells: the sub-cell and the fraction in it.
VDBLIGHT_NANO_FN pnanovdb_int32_t vdblight_nano_split_local(PNANOVDB_INOUT(float) f, pnanovdb_int32_t K) {
    float u = PNANOVDB_DEREF(f) * pnanovdb_int32_to_float(K);
    pnanovdb_int32_t i = pnanovdb_float_to_int32(u);
    if (i > K - 1) i = K - 1;
    PNANOVDB_DEREF(f) = u - pnanovdb_int32_to_float(i);
    return i;
}

// The index of node ijk in its level's channel arrays: the value of the level's vdblight_nodes
// grid (accessor acc) there.
VDBLIGHT_NANO_FN pnanovdb_uint32_t vdblight_nano_node_index(pnanovdb_buf_t buf, PNANOVDB_INOUT(pnanovdb_readaccessor_t) acc,
                                                           pnanovdb_coord_t ijk) {
    return pnanovdb_read_uint32(buf, pnanovdb_readaccessor_get_value_address(PNANOVDB_GRID_TYPE_UINT32, buf, acc, PNANOVDB_REF(ijk)));
}

VDBLIGHT_NANO_FN pnanovdb_coord_t vdblight_nano_corner(PNANOVDB_IN(vdblight_nano_cell_t) cell, pnanovdb_int32_t c) {
    pnanovdb_coord_t ijk;
    ijk.x = PNANOVDB_DEREF(cell).lo.x + (c & 1) * PNANOVDB_DEREF(cell).step_x;
    ijk.y = PNANOVDB_DEREF(cell).lo.y + ((c >> 1) & 1) * PNANOVDB_DEREF(cell).step_y;
    ijk.z = PNANOVDB_DEREF(cell).lo.z + (c >> 2) * PNANOVDB_DEREF(cell).step_z;
    return ijk;
}

// Visibility of a query point at offset (ox, oy, oz) in cells from a corner node whose depth
// values start at address `a` in the first depth array (the next three at `stride` each):
// per axis the face on the point's side, Chebyshev's bound past mean + 0.02, the product cubed.
VDBLIGHT_NANO_FN float vdblight_nano_depth_visibility(pnanovdb_buf_t buf, pnanovdb_address_t a, pnanovdb_uint32_t stride,
                                                      float ox, float oy, float oz) {
    float o[3];
    o[0] = ox;
    o[1] = oy;
    o[2] = oz;
    float v = 1.0f;
    for (pnanovdb_uint32_t axis = 0u; axis < 3u; ++axis) {
        pnanovdb_bool_t negative = o[axis] < 0.0f;
        // arrays: depth_mean_pos, depth_mean_neg, depth_sigma_pos, depth_sigma_neg
        pnanovdb_uint32_t mean_grid = negative ? 1u : 0u;
        float mu = pnanovdb_read_float(buf, pnanovdb_address_offset(pnanovdb_address_offset_product(a, stride, mean_grid), 4u * axis));
        float sigma = pnanovdb_read_float(buf, pnanovdb_address_offset(pnanovdb_address_offset_product(a, stride, mean_grid + 2u), 4u * axis));
        float e = (o[axis] < 0.0f ? -o[axis] : o[axis]) - mu - 0.02f;
        if (e <= 0.0f) continue;
        float s2 = sigma * sigma + 0.02f * 0.02f;
        v *= s2 / (s2 + e * e);
    }
    return v * v * v;
}

// The cell of world point x (clamped into the node box) and its eight weights.
VDBLIGHT_NANO_FN vdblight_nano_cell_t vdblight_nano_locate(pnanovdb_buf_t buf, PNANOVDB_IN(vdblight_nano_volume_t) v, pnanovdb_vec3_t x) {
    vdblight_nano_cell_t cell;
    pnanovdb_vec3_t u = pnanovdb_grid_world_to_indexf(buf, PNANOVDB_DEREF(v).first[0], PNANOVDB_REF(x));
    cell.level = 0;
    cell.f[0] = 0.0f;
    cell.f[1] = 0.0f;
    cell.f[2] = 0.0f;
    cell.lo.x = 0;
    cell.lo.y = 0;
    cell.lo.z = 0;
    cell.step_x = PNANOVDB_DEREF(v).dims_x > 1 ? 1 : 0;
    cell.step_y = PNANOVDB_DEREF(v).dims_y > 1 ? 1 : 0;
    cell.step_z = PNANOVDB_DEREF(v).dims_z > 1 ? 1 : 0;
    if (cell.step_x != 0) cell.lo.x = vdblight_nano_split(u.x, PNANOVDB_DEREF(v).dims_x, PNANOVDB_REF(cell.f[0]));
    if (cell.step_y != 0) cell.lo.y = vdblight_nano_split(u.y, PNANOVDB_DEREF(v).dims_y, PNANOVDB_REF(cell.f[1]));
    if (cell.step_z != 0) cell.lo.z = vdblight_nano_split(u.z, PNANOVDB_DEREF(v).dims_z, PNANOVDB_REF(cell.f[2]));
    // Down the refined cells (a multi-level volume has at least two nodes along every axis).
    pnanovdb_int32_t K = PNANOVDB_DEREF(v).refine;
    pnanovdb_bool_t descend = cell.step_x != 0 && cell.step_y != 0 && cell.step_z != 0;
    while (descend && cell.level + 1 < PNANOVDB_DEREF(v).levels) {
        pnanovdb_grid_handle_t mask = PNANOVDB_DEREF(v).refined[cell.level];
        pnanovdb_readaccessor_t acc;
        pnanovdb_readaccessor_init(PNANOVDB_REF(acc), pnanovdb_tree_get_root(buf, pnanovdb_grid_get_tree(buf, mask)));
        if (!pnanovdb_readaccessor_is_active(PNANOVDB_GRID_TYPE_FLOAT, buf, PNANOVDB_REF(acc), PNANOVDB_REF(cell.lo))) break;
        cell.lo.x = cell.lo.x * K + vdblight_nano_split_local(PNANOVDB_REF(cell.f[0]), K);
        cell.lo.y = cell.lo.y * K + vdblight_nano_split_local(PNANOVDB_REF(cell.f[1]), K);
        cell.lo.z = cell.lo.z * K + vdblight_nano_split_local(PNANOVDB_REF(cell.f[2]), K);
        cell.level += 1;
    }
    float wx[2], wy[2], wz[2];
    wx[0] = 1.0f - cell.f[0];
    wx[1] = cell.f[0];
    wy[0] = 1.0f - cell.f[1];
    wy[1] = cell.f[1];
    wz[0] = 1.0f - cell.f[2];
    wz[1] = cell.f[2];
    for (pnanovdb_int32_t c = 0; c < 8; ++c) cell.w[c] = wx[c & 1] * wy[(c >> 1) & 1] * wz[c >> 2];
    // Depth weights, in cells of the finest level only (a coarser leaf cell holds no geometry).
    if (PNANOVDB_DEREF(v).depth != 0 && cell.level + 1 == PNANOVDB_DEREF(v).levels) {
        pnanovdb_readaccessor_t acc;
        pnanovdb_readaccessor_init(PNANOVDB_REF(acc), pnanovdb_tree_get_root(buf, pnanovdb_grid_get_tree(buf, PNANOVDB_DEREF(v).first[cell.level])));
        pnanovdb_uint32_t stride = PNANOVDB_DEREF(v).stride[cell.level];
        pnanovdb_address_t depth0 = pnanovdb_address_offset_product(PNANOVDB_DEREF(v).channels0[cell.level], stride,
                                                                    pnanovdb_int32_as_uint32(PNANOVDB_DEREF(v).channels));
        float sum = 0.0f;
        for (pnanovdb_int32_t c = 0; c < 8; ++c) {
            pnanovdb_uint32_t node = vdblight_nano_node_index(buf, PNANOVDB_REF(acc), vdblight_nano_corner(PNANOVDB_REF(cell), c));
            pnanovdb_address_t a = pnanovdb_address_offset_product(depth0, 12u, node);
            float vis = vdblight_nano_depth_visibility(buf, a, stride,
                                                       cell.f[0] - pnanovdb_int32_to_float(c & 1),
                                                       cell.f[1] - pnanovdb_int32_to_float((c >> 1) & 1),
                                                       cell.f[2] - pnanovdb_int32_to_float(c >> 2));
            cell.w[c] *= vis + 1e-6f;
            sum += cell.w[c];
        }
        float inv = 1.0f / sum;
        for (pnanovdb_int32_t c = 0; c < 8; ++c) cell.w[c] *= inv;
    }
    return cell;
}

// The clamped-cosine constant A_l of coefficient j (band l): pi, 2 pi / 3, pi / 4, 0, -pi / 24.
VDBLIGHT_NANO_FN float vdblight_nano_sh_lobe(pnanovdb_int32_t j) {
    if (j == 0) return 3.14159274f;
    if (j < 4) return 2.09439516f;
    if (j < 9) return 0.785398185f;
    if (j < 16) return 0.0f;
    return -0.130899698f;
}

// Y_j(n) for coefficient j of SH order 4 or less: the explicit polynomials of docs/engines.md
// ("Shaders for sh:N"). `unrolled`: bands 0..2 as the sh2 lookup writes them (3 z z - 1).
VDBLIGHT_NANO_FN float vdblight_nano_sh_y(pnanovdb_int32_t j, pnanovdb_vec3_t n, pnanovdb_bool_t unrolled) {
    float x = n.x, y = n.y, z = n.z;
    float x2 = x * x, y2 = y * y, z2 = z * z;
    if (j == 0) return 0.282094792f;
    if (j == 1) return 0.488602512f * y;
    if (j == 2) return 0.488602512f * z;
    if (j == 3) return 0.488602512f * x;
    if (j == 4) return 1.092548431f * x * y;
    if (j == 5) return 1.092548431f * y * z;
    if (j == 6) return unrolled ? 0.315391565f * (3.0f * z * z - 1.0f) : 0.315391565f * (3.0f * z2 - 1.0f);
    if (j == 7) return 1.092548431f * x * z;
    if (j == 8) return unrolled ? 0.546274215f * (x * x - y * y) : 0.546274215f * (x2 - y2);
    if (j == 9) return 0.590043590f * y * (3.0f * x2 - y2);
    if (j == 10) return 2.890611443f * x * y * z;
    if (j == 11) return 0.457045799f * y * (5.0f * z2 - 1.0f);
    if (j == 12) return 0.373176333f * z * (5.0f * z2 - 3.0f);
    if (j == 13) return 0.457045799f * x * (5.0f * z2 - 1.0f);
    if (j == 14) return 1.445305721f * z * (x2 - y2);
    if (j == 15) return 0.590043590f * x * (x2 - 3.0f * y2);
    if (j == 16) return 2.503342942f * x * y * (x2 - y2);
    if (j == 17) return 1.770130770f * y * z * (3.0f * x2 - y2);
    if (j == 18) return 0.946174696f * x * y * (7.0f * z2 - 1.0f);
    if (j == 19) return 0.669046544f * y * z * (7.0f * z2 - 3.0f);
    if (j == 20) return 0.105785547f * (35.0f * z2 * z2 - 30.0f * z2 + 3.0f);
    if (j == 21) return 0.669046544f * x * z * (7.0f * z2 - 3.0f);
    if (j == 22) return 0.473087348f * (x2 - y2) * (7.0f * z2 - 1.0f);
    if (j == 23) return 1.770130770f * x * z * (x2 - 3.0f * y2);
    return 0.625835735f * (x2 * x2 - 6.0f * x2 * y2 + y2 * y2);
}

#include "vdblight_nanovdb_lights.h"  // vdblight_nano_light_irradiance, vdblight_nano_edge_visibility

// Irradiance (W/m^2 per colour) at world point x for unit normal n; (0, 0, 0) for a volume
// this lookup does not read (v.supported false).
VDBLIGHT_NANO_FN pnanovdb_vec3_t vdblight_nano_irradiance(pnanovdb_buf_t buf, PNANOVDB_IN(vdblight_nano_volume_t) v,
                                                          pnanovdb_vec3_t x, pnanovdb_vec3_t n) {
    pnanovdb_vec3_t e;
    e.x = 0.0f;
    e.y = 0.0f;
    e.z = 0.0f;
    if (!PNANOVDB_DEREF(v).supported) return e;
    vdblight_nano_cell_t cell = vdblight_nano_locate(buf, v, x);
    pnanovdb_grid_handle_t g0 = PNANOVDB_DEREF(v).first[cell.level];
    pnanovdb_uint32_t stride = PNANOVDB_DEREF(v).stride[cell.level];
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(PNANOVDB_REF(acc), pnanovdb_tree_get_root(buf, pnanovdb_grid_get_tree(buf, g0)));
    pnanovdb_address_t corner[8];
    pnanovdb_uint32_t node[8];
    for (pnanovdb_int32_t c = 0; c < 8; ++c) {
        node[c] = vdblight_nano_node_index(buf, PNANOVDB_REF(acc), vdblight_nano_corner(PNANOVDB_REF(cell), c));
        corner[c] = pnanovdb_address_offset_product(PNANOVDB_DEREF(v).channels0[cell.level], 12u, node[c]);
    }
    pnanovdb_int32_t count = (PNANOVDB_DEREF(v).sh_order + 1) * (PNANOVDB_DEREF(v).sh_order + 1);
    pnanovdb_bool_t folded = PNANOVDB_DEREF(v).folded != 0;
    for (pnanovdb_int32_t j = 0; j < count; ++j) {
        float lobe = vdblight_nano_sh_lobe(j);
        if (lobe == 0.0f) continue;  // band 3: no irradiance
        // sh:N: the channel blended, then times A_l Y_j(n); sh2: A_l first (the same sums, other bits).
        float pre = folded ? lobe : 1.0f;
        float bw = folded ? vdblight_nano_sh_y(j, n, PNANOVDB_TRUE) : lobe * vdblight_nano_sh_y(j, n, PNANOVDB_FALSE);
        float r = 0.0f, g = 0.0f, b = 0.0f;
        for (pnanovdb_int32_t c = 0; c < 8; ++c) {
            pnanovdb_address_t a = pnanovdb_address_offset_product(corner[c], stride, pnanovdb_int32_as_uint32(j));
            r += (pnanovdb_read_float(buf, a) * pre) * cell.w[c];
            g += (pnanovdb_read_float(buf, pnanovdb_address_offset(a, 4u)) * pre) * cell.w[c];
            b += (pnanovdb_read_float(buf, pnanovdb_address_offset(a, 8u)) * pre) * cell.w[c];
        }
        e.x += r * bw;
        e.y += g * bw;
        e.z += b * bw;
    }
    // --direct occlusion: the listed lights times their visibility, with the same weights (level
    // 0's arrays: occlusion volumes have one level), summed apart and then added to the SH part,
    // as query sums them (query/direct_sum.h): the same bits with several lights.
    pnanovdb_vec3_t direct = pnanovdb_vec3_uniform(0.0f);
    for (pnanovdb_int32_t c = 0; c < 8 && PNANOVDB_DEREF(v).visibility > 0; ++c)
        corner[c] = pnanovdb_address_offset_product(PNANOVDB_DEREF(v).visibility0, 4u, node[c]);
    for (pnanovdb_int32_t i = 0; i < PNANOVDB_DEREF(v).visibility; ++i) {
        float vis = 0.0f;
        if (PNANOVDB_DEREF(v).shadow_edges > 0)
            vis = vdblight_nano_edge_visibility(buf, v, PNANOVDB_REF(cell), node, x, i);
        else
            for (pnanovdb_int32_t c = 0; c < 8; ++c)
                vis += cell.w[c] * pnanovdb_read_float(buf, pnanovdb_address_offset_product(corner[c], PNANOVDB_DEREF(v).visibility_stride, pnanovdb_int32_as_uint32(i)));
        if (vis > 0.0f) direct = pnanovdb_vec3_add(direct, vdblight_nano_scale(vdblight_nano_light_irradiance(buf, v, i, x, n), vis));
    }
    return pnanovdb_vec3_add(e, direct);
}

// The visibility (0..1) of listed light i of a `--direct occlusion` volume at x, interpolated
// with the cell's weights as the SH (level 0 holds the visibility grids: single-level volumes).
VDBLIGHT_NANO_FN float vdblight_nano_light_visibility(pnanovdb_buf_t buf, PNANOVDB_IN(vdblight_nano_volume_t) v,
                                                      pnanovdb_vec3_t x, pnanovdb_int32_t i) {
    if (!PNANOVDB_DEREF(v).supported || i < 0 || i >= PNANOVDB_DEREF(v).visibility) return 1.0f;
    vdblight_nano_cell_t cell = vdblight_nano_locate(buf, v, x);
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(PNANOVDB_REF(acc), pnanovdb_tree_get_root(buf, pnanovdb_grid_get_tree(buf, PNANOVDB_DEREF(v).first[0])));
    pnanovdb_address_t light = pnanovdb_address_offset_product(PNANOVDB_DEREF(v).visibility0, PNANOVDB_DEREF(v).visibility_stride,
                                                               pnanovdb_int32_as_uint32(i));
    pnanovdb_uint32_t node[8];
    for (pnanovdb_int32_t c = 0; c < 8; ++c)
        node[c] = vdblight_nano_node_index(buf, PNANOVDB_REF(acc), vdblight_nano_corner(PNANOVDB_REF(cell), c));
    if (PNANOVDB_DEREF(v).shadow_edges > 0) return vdblight_nano_edge_visibility(buf, v, PNANOVDB_REF(cell), node, x, i);
    float s = 0.0f;
    for (pnanovdb_int32_t c = 0; c < 8; ++c) s += pnanovdb_read_float(buf, pnanovdb_address_offset_product(light, 4u, node[c])) * cell.w[c];
    return s;
}

#endif  // VDBLIGHT_NANOVDB_H
