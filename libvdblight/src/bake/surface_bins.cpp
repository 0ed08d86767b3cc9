#include "surface_bins.h"

#include <algorithm>
#include <cmath>

#include "vdblight/core/errors.h"

namespace vdblight::bake_detail {

namespace {
/// The signed axis of n's largest component: 2a for +axis a, 2a + 1 for -axis a.
int faceOf(const Vec3f& n) {
    const float ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
    const int a = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
    return 2 * a + (n[a] < 0 ? 1 : 0);
}

constexpr double kStepsPerScale = 1073741824.0;  // 2^30
constexpr double kMaxSteps = 1099511627776.0;    // 2^40: a sample's clamp, 2^10 radianceScale
// Sample positions: cell units shifted by one cell (so that a point a little outside the node
// box is positive), 2^20 steps per cell.
constexpr double kPosSteps = 1048576.0;
constexpr double kPosShift = 1.0;
}  // namespace

SurfaceBins::SurfaceBins(const Tracer& tracer, const GridSpec& grid, double radianceScale)
    : grid_(grid), tracer_(tracer), cells_(SurfaceBinSums::cells(grid)), unit_(radianceScale / kStepsPerScale) {
    cellCount_ = std::size_t(SurfaceBinSums::cellCount(cells_));
    cellPtrs_.reset(new std::atomic<Cell*>[cellCount_]);
    for (std::size_t c = 0; c < cellCount_; ++c) cellPtrs_[c].store(nullptr, std::memory_order_relaxed);
}

SurfaceBins::SurfaceBins(const Tracer& tracer, const GridSpec& grid, const SurfaceBinSums& sums)
    : SurfaceBins(tracer, grid, 1.0) {
    sums.validate(cells_);
    unit_ = sums.unit;
    const uint64_t* v = sums.values.data();
    for (const uint64_t index : sums.cellIndices) {
        Cell& cell = cellForAdd(std::size_t(index));
        for (Bin& bin : cell) {
            for (int ch = 0; ch < 3; ++ch) bin.sum[ch].store(v[ch], std::memory_order_relaxed);
            bin.count.store(v[3], std::memory_order_relaxed);
            for (int a = 0; a < 3; ++a) bin.pos[a].store(v[4 + a], std::memory_order_relaxed);
            v += SurfaceBinSums::kValuesPerBin;
        }
    }
}

SurfaceBins::~SurfaceBins() {
    for (std::size_t c = 0; c < cellCount_; ++c) delete cellPtrs_[c].load(std::memory_order_relaxed);
}

SurfaceBinSums SurfaceBins::sums() const {
    SurfaceBinSums s;
    s.unit = unit_;
    s.cellIndices.reserve(cellsHeld());
    s.values.reserve(cellsHeld() * SurfaceBinSums::kValuesPerCell);
    for (std::size_t c = 0; c < cellCount_; ++c) {  // ascending: the sums' order
        const Cell* cell = cellPtrs_[c].load(std::memory_order_acquire);
        if (!cell) continue;
        s.cellIndices.push_back(c);
        for (const Bin& bin : *cell) {
            for (int ch = 0; ch < 3; ++ch) s.values.push_back(bin.sum[ch].load(std::memory_order_relaxed));
            s.values.push_back(bin.count.load(std::memory_order_relaxed));
            for (int a = 0; a < 3; ++a) s.values.push_back(bin.pos[a].load(std::memory_order_relaxed));
        }
    }
    return s;
}

std::size_t SurfaceBins::cellsHeld() const {
    std::size_t held = 0;
    for (std::size_t c = 0; c < cellCount_; ++c) held += cellPtrs_[c].load(std::memory_order_relaxed) != nullptr;
    return held;
}

std::size_t SurfaceBins::cellIndex(int i, int j, int k) const {
    i = std::clamp(i, 0, cells_[0] - 1);
    j = std::clamp(j, 0, cells_[1] - 1);
    k = std::clamp(k, 0, cells_[2] - 1);
    return std::size_t(SurfaceBinSums::cellIndex(cells_, i, j, k));
}

SurfaceBins::Cell& SurfaceBins::cellForAdd(std::size_t index) {
    std::atomic<Cell*>& ptr = cellPtrs_[index];
    Cell* cell = ptr.load(std::memory_order_acquire);
    if (cell) return *cell;
    // First sample here: allocate; if another thread won the race, use its cell. Which thread
    // allocates does not change the sums (integer additions).
    auto fresh = std::make_unique<Cell>();
    if (ptr.compare_exchange_strong(cell, fresh.get(), std::memory_order_acq_rel, std::memory_order_acquire))
        return *fresh.release();
    return *cell;
}

void SurfaceBins::add(const Vec3f& p, const Vec3f& n, const Rgb& irradiance) {
    int c[3];
    double at[3];  // p in cells of the grid, for the cell and the centroid
    for (int a = 0; a < 3; ++a) {
        at[a] = (double(p[a]) - grid_.origin[a]) / grid_.spacing;
        c[a] = int(std::clamp(std::floor(at[a]), -1.0, 1e9));
    }
    Bin& bin = cellForAdd(cellIndex(c[0], c[1], c[2]))[std::size_t(faceOf(n))];
    for (int ch = 0; ch < 3; ++ch) {
        const double steps = double(irradiance[ch]) / unit_;
        // !(x > 0) also takes NaN: radiance is never negative.
        const uint64_t q = steps > 0 ? roundNonNegative(std::min(steps, kMaxSteps)) : 0;
        bin.sum[ch].fetch_add(q, std::memory_order_relaxed);
    }
    bin.count.fetch_add(1, std::memory_order_relaxed);
    for (int a = 0; a < 3; ++a) {
        const double u = std::clamp(at[a] + kPosShift, 0.0, 1e6);
        bin.pos[a].fetch_add(roundNonNegative(u * kPosSteps), std::memory_order_relaxed);
    }
}

uint64_t SurfaceBins::samples() const {
    uint64_t total = 0;
    for (std::size_t c = 0; c < cellCount_; ++c)
        if (const Cell* cell = cellPtrs_[c].load(std::memory_order_acquire))
            for (const Bin& bin : *cell) total += bin.count.load(std::memory_order_relaxed);
    return total;
}

Rgb SurfaceBins::meanIrradiance() const {
    double sum[3] = {0, 0, 0};
    for (std::size_t c = 0; c < cellCount_; ++c)
        if (const Cell* cell = cellPtrs_[c].load(std::memory_order_acquire))
            for (const Bin& bin : *cell)
                for (int ch = 0; ch < 3; ++ch) sum[ch] += double(bin.sum[ch].load(std::memory_order_relaxed));
    const double n = double(std::max<uint64_t>(1, samples()));
    return Rgb(float(sum[0] * unit_ / n), float(sum[1] * unit_ / n), float(sum[2] * unit_ / n));
}

bool SurfaceBins::irradiance(const Vec3f& p, const Vec3f& n, Rgb& out, RayCount& rays) const {
    const int face = faceOf(n);
    const int axis = face / 2;
    int base[3];
    double frac[3];
    for (int a = 0; a < 3; ++a) {
        const double u = (double(p[a]) - grid_.origin[a]) / grid_.spacing;
        if (a == axis) {  // the cell row along the normal that holds p
            base[a] = int(std::clamp(std::floor(u), -1.0, 1e9));
            frac[a] = 0;
            continue;
        }
        // Cell centres sit at half-integers: blend the two nearest along each tangent axis.
        const double v = std::clamp(u - 0.5, 0.0, double(cells_[a] - 1));
        base[a] = std::min(int(v), std::max(0, cells_[a] - 2));
        frac[a] = cells_[a] > 1 ? v - base[a] : 0.0;
    }
    double sum[3] = {0, 0, 0}, count = 0;
    for (int corner = 0; corner < 4; ++corner) {
        int idx[3] = {base[0], base[1], base[2]};
        double w = 1;
        int bit = 0;
        for (int a = 0; a < 3; ++a) {
            if (a == axis) continue;
            const int step = (corner >> bit++) & 1;
            idx[a] += step;
            w *= step ? frac[a] : 1.0 - frac[a];
        }
        if (!(w > 0)) continue;
        const Cell* cell = cellPtrs_[cellIndex(idx[0], idx[1], idx[2])].load(std::memory_order_acquire);
        if (!cell) continue;  // no sample in this cell
        const Bin& bin = (*cell)[std::size_t(face)];
        const double samples = double(bin.count.load(std::memory_order_relaxed));
        if (samples < 1) continue;
        // The bin's samples' centroid, lifted off the surface a little: a bin whose centroid p
        // does not see holds another surface's light (a floor cell that a thin wall crosses
        // holds both rooms' floor).
        Vec3f centroid;
        for (int a = 0; a < 3; ++a)
            centroid[a] = float(grid_.origin[a] +
                                (double(bin.pos[a].load(std::memory_order_relaxed)) / kPosSteps / samples - kPosShift) *
                                    grid_.spacing);
        const Vec3f d = centroid + n * float(0.02 * grid_.spacing) - p;
        if (dot(d, d) > 1e-12f) {
            ++rays.occluded;
            if (tracer_.occluded(Ray{p, d, 0.0f, 1.0f})) continue;
        }
        for (int ch = 0; ch < 3; ++ch) sum[ch] += w * double(bin.sum[ch].load(std::memory_order_relaxed));
        count += w * samples;
    }
    if (!(count >= 1.0)) return false;  // (almost) no path came here: the path goes on
    out = Rgb(float(sum[0] * unit_ / count), float(sum[1] * unit_ / count), float(sum[2] * unit_ / count));
    return true;
}

double radianceScale(const Scene& scene, double spacing) {
    double s = 0;
    for (const Material& m : scene.materials) s = std::max(s, double(maxComponent(m.emission)));
    s = std::max(s, double(maxComponent(scene.sky.constant)));
    if (scene.sky.map)
        for (const Rgb& t : scene.sky.map->texels) s = std::max(s, double(maxComponent(t)));
    const double area = spacing * spacing;
    for (const PointLight& l : scene.pointLights) s = std::max(s, double(maxComponent(l.intensity)) / area);
    for (const SpotLight& l : scene.spotLights) s = std::max(s, double(maxComponent(l.intensity)) / area);
    for (const DirectionalLight& l : scene.directionalLights) s = std::max(s, double(maxComponent(l.irradiance)) / kPi);
    return std::isfinite(s) && s > 0 ? s : 1.0;
}

}  // namespace vdblight::bake_detail
