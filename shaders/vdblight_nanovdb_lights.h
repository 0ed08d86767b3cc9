// vdblight_nanovdb_lights.h: the exact unshadowed irradiance of the lights a `--direct
// occlusion` volume lists, read from the light records of `vdblight_meta` (docs/engines.md,
// "NanoVDB"; the formulas of docs/format.md, "Direct light", as
// libvdblight/src/light/exact_irradiance.cpp evaluates them, here in float). Part of
// vdblight_nanovdb.h, which includes it after the meta reader and the volume struct.
#ifndef VDBLIGHT_NANOVDB_LIGHTS_H
#define VDBLIGHT_NANOVDB_LIGHTS_H

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

// Lambert's term theta (n . gamma) of the edge a -> b (relative to the receiver).
VDBLIGHT_NANO_FN float vdblight_nano_edge(pnanovdb_vec3_t a, pnanovdb_vec3_t b, pnanovdb_vec3_t n) {
    pnanovdb_vec3_t c = vdblight_nano_cross(a, b);
    float len = VDBLIGHT_NANO_SQRT(vdblight_nano_dot(c, c));
    if (!(len > 0.0f)) return 0.0f;  // an edge pointing at the receiver subtends no angle
    return VDBLIGHT_NANO_ATAN2(len, vdblight_nano_dot(a, b)) * vdblight_nano_dot(n, c) / len;
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

#endif  // VDBLIGHT_NANOVDB_LIGHTS_H
