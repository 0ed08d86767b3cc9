// The normals at which a probe pass's surface cache (surface_cache.h) stores each node's
// irradiance of reflected light and sky. (Internal to the bake module.)
//
// Why not SH order 2 (the cache's representation before issue 15's fourth session): the
// cache is read at surfaces, where light often arrives at grazing angles (through a door,
// along a wall, from the sky near the horizon) or head-on. SH2's clamped-cosine kernel gives
// a direction at the normal 1.0625 times its true irradiance, 0.094 of it at the horizon,
// where the truth is 0, and up to 0.05 just below it; at a floor lit by a sky band 0..10
// degrees above the horizon it read 1.63 times the irradiance (tests/probe_cache_test.cpp).
//
// Instead each node keeps the exact clamped-cosine irradiance of its samples for the vertex
// directions of an octahedral map with kN cells a side (Praun & Hoppe 2003; DDGI stores
// irradiance in octahedral texels too, Majercik et al. 2019): kN^2 + 2 directions once the
// folded border's duplicates are merged, the six axes among them; neighbours are about 27
// degrees apart at the map's centre and farther along its folds. A normal between vertices
// interpolates bilinearly in the map: exact at the vertices (the axes: walls, floors,
// ceilings); the four directions lie within 70 degrees of the normal (64 measured), and for the hardest
// field, a single distant direction, the read is within 0.18 of its head-on value
// (tests/probe_cache_test.cpp; broad reflected light reads far closer). Memory: 456 B per
// node while a probe bake runs (SH2: 108 B).
#pragma once

#include "vdblight/math.h"

namespace vdblight::bake_detail::cache_dirs {

constexpr int kN = 6;                        ///< octahedral cells a side (even: the axes are vertices)
constexpr int kDirections = kN * kN + 2;     ///< distinct vertex directions
constexpr int kVertices = (kN + 1) * (kN + 1);

struct Table {
    Vec3f dir[kDirections];  ///< unit directions, stored order
    int vertex[kVertices];   ///< vertex (i, j) at [j * (kN + 1) + i]: its index in dir
};

/// The directions (built once).
const Table& table();

/// The four stored directions around unit normal n and their bilinear weights (sum 1).
void weights(const Vec3f& n, int idx[4], float w[4]);

}  // namespace vdblight::bake_detail::cache_dirs
