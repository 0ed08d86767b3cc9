// The sampling of a node that the bins gather and the generic basis gather share: directions
// stratified in the 2 R^2 equal-area cells of bins.h (scrambled Sobol (0,2) points inside each
// cell, uniform on the sphere as a whole), one NEE sample of the emissive triangles per
// direction sample (MIS, power heuristic, against the uniform sphere pdf), and the punctual
// lights exactly. (Internal to the bake module.)
//
// The callbacks get: sample(cell, direction, radiance) for every direction sample and
// cellDone(cell, scale) after each cell's samples (scale = 1 / (pdf * samples), the same for
// every sample); light(direction, value, samples) for NEE samples (value / samples is their
// contribution to the integral over the sphere) and for punctual lights (samples 1).
#pragma once

#include <cmath>
#include <vector>

#include "vdblight/basis/bins.h"
#include "vdblight/light/light.h"
#include "vdblight/sampling/sampling.h"

namespace vdblight::bake_detail {

enum StratifiedDimension : uint64_t { kStratDirection = 11, kStratLightPoint = 12, kStratLightChoice = 13, kStratPath = 14 };
constexpr float kUniformSpherePdf = float(1.0 / (4.0 * kPi));

template <class Sample, class CellDone, class Light>
void sampleStratifiedSphere(const RadianceEstimator& estimator, const Vec3f& x, int resolution, uint32_t samplesPerCell,
                            uint64_t seed, uint64_t streamIndex, RayCount& count, Sample&& sample, CellDone&& cellDone,
                            Light&& light) {
    const int R = resolution, cells = 2 * R * R;
    const uint64_t stream = hashCombine(seed, streamIndex);
    Rng rng(stream, kStratPath);
    const double lightOffset = toUnitDouble(hashCombine(stream, kStratLightChoice));
    const uint64_t dirSeed = hashCombine(stream, kStratDirection), lightSeed = hashCombine(stream, kStratLightPoint);
    const bool nee = estimator.hasEmissiveTriangles();
    const double total = double(cells) * samplesPerCell;
    const double scale = 4.0 * kPi / total;  // 1 / (pdf * samples): every sample is uniform on the sphere

    for (int b = 0; b < cells; ++b) {
        const int h = b / (R * R), iv = b % (R * R) / R, iu = b % R;
        const uint64_t cellSeed = hashCombine(dirSeed, uint64_t(b));
        for (uint32_t s = 0; s < samplesPerCell; ++s) {
            float u, v;
            sobol02(s, cellSeed, u, v);  // stratified inside the cell
            const Vec3f dir = bins::squareToDirection(h, (float(iu) + u) / float(R), (float(iv) + v) / float(R));
            sample(b, dir, estimator.gatherRadiance(x, dir, kUniformSpherePdf, rng, count));
        }
        cellDone(b, scale);
    }
    if (nee) {  // one NEE sample per direction sample
        const uint32_t n = uint32_t(total);
        for (uint32_t i = 0; i < n; ++i) {
            float u, v;
            sobol02(i, lightSeed, u, v);
            double w = radicalInverse(3, i) + lightOffset;
            w -= std::floor(w);
            LightSample s;
            if (!estimator.sampleEmissiveTriangles(x, u, v, float(w), s, count)) continue;
            light(s.direction, Rgbd(s.weight * misWeight(s.pdf, kUniformSpherePdf)), total);
        }
    }
    std::vector<LightSample> punctual;  // deltas: exact
    estimator.punctualLights(x, punctual, count);
    for (const LightSample& s : punctual) light(s.direction, Rgbd(s.weight), 1.0);
}

}  // namespace vdblight::bake_detail
