// Volumes with random node values, for tests of lookups and exports against the reference
// lookups: one uniform level or a small bilevel / adaptive layout, of any basis.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "vdblight/basis/depth_moments.h"
#include "vdblight/layout/layout.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/volume/volume.h"

namespace vdblight::test {

/// One level of `basis` (basis.channelCount() RGB values per node) of nx x ny x nz nodes
/// `spacing` apart from (-0.5, 0.25, 1.0), every value drawn uniformly from [-0.5, 1.5) by Rng(seed).
inline Volume randomUniformVolume(const BasisDesc& basis, int nx, int ny, int nz, double spacing, uint64_t seed) {
    Volume v;
    v.basis = basis;
    VolumeLevel level;
    level.grid.origin = {-0.5, 0.25, 1.0};
    level.grid.spacing = spacing;
    level.grid.nx = nx;
    level.grid.ny = ny;
    level.grid.nz = nz;
    Rng rng(seed);
    level.data.resize(level.grid.nodeCount() * std::size_t(basis.channelCount()) * 3);
    for (float& f : level.data) f = rng.uniform() * 2.0f - 0.5f;
    v.levels.push_back(level);
    return v;
}

/// randomUniformVolume of SH order 2.
inline Volume randomShVolume(int nx, int ny, int nz, double spacing, uint64_t seed) {
    return randomUniformVolume(BasisDesc::sh2(), nx, ny, nz, spacing, seed);
}

/// Levels (refine 2) over a 5^3 lattice of spacing 0.225 from (0.05, 0.05, 0.05), refined
/// around a triangle near the z = 0 face and one in the middle of the box. Every stored node
/// holds basis.channelCount() RGB values drawn uniformly from [lo, hi) by std::mt19937(seed),
/// level after level. Seam nodes are left as drawn (applySeamConstraints makes them a bake's).
inline Volume randomLevelsVolume(LayoutKind kind, int levels, const BasisDesc& basis, uint32_t seed, float lo, float hi) {
    std::vector<Vec3f> pos = {{0.0f, 0.0f, 0.02f}, {1.0f, 0.0f, 0.02f}, {1.0f, 0.97f, 0.02f},
                              {0.3f, 0.2f, 0.5f},  {0.7f, 0.4f, 0.8f},  {0.4f, 0.8f, 0.6f}};
    std::vector<uint32_t> idx = {0, 1, 2, 3, 4, 5};
    GridSpec g0;
    g0.origin = Vec3d(0.05, 0.05, 0.05);
    g0.spacing = 0.9 / 4;
    g0.nx = g0.ny = g0.nz = 5;
    LevelsPlacement p;
    p.kind = kind;
    p.refine = 2;
    p.levels = levels;
    const std::size_t floats = std::size_t(basis.channelCount()) * 3;
    const LevelLayout layout = placeLevels(g0, pos, idx, p, floats * 4);
    Volume v;
    v.basis = basis;
    v.levels = volumeLevels(layout.levels);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(lo, hi);
    for (VolumeLevel& l : v.levels) {
        l.data.resize(l.storedNodes() * floats);
        for (float& f : l.data) f = u(rng);
    }
    return v;
}

/// Random depth moments on every level (depth_moments.h), as the bake stores them (k/255):
/// means in [0, 1), sigmas in [0, 0.3), so that every branch of the visibility test is taken.
inline void randomDepth(Volume& v, uint64_t seed) {
    Rng rng(seed, 11);
    for (VolumeLevel& l : v.levels) {
        l.depth.resize(l.storedNodes() * depth::kFloatsPerNode);
        for (std::size_t i = 0; i < l.depth.size(); ++i) {
            const bool sigma = (i % depth::kFloatsPerNode) >= 6;
            l.depth[i] = depth::quantize(sigma ? 0.3 * rng.uniform() : rng.uniform());
        }
    }
}

/// Every level's node values (already sized) drawn uniformly from [-0.3, 1.7).
inline void randomData(Volume& v, uint64_t seed) {
    Rng rng(seed, 5);
    for (VolumeLevel& l : v.levels)
        for (float& f : l.data) f = rng.uniform() * 2.0f - 0.3f;
}

}  // namespace vdblight::test
