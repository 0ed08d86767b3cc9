// The matrices section of a PRT file: the PCA bases and the transfer matrices as sparse
// float grids whose voxel (a, b, c) is a matrix entry (prt_io_sections.h).
#include <algorithm>
#include <cmath>

#include "prt_io_sections.h"

namespace vdblight::prt_io {

namespace {
using openvdb::Coord;
constexpr float kHalfMax = 65504.0f;

/// Stores row-major matrix rows (k, j) of a basis under cluster c: voxel (c, k, j).
void putBasis(openvdb::FloatGrid& grid, const PcaBasis& b, int c, float thr, Counter& n) {
    auto acc = grid.getAccessor();
    for (int j = 0; j < b.dim; ++j) acc.setValue(Coord(c, -1, j), b.mean[std::size_t(j)]);  // row -1: the mean
    n.values += std::size_t(b.dim);
    for (int k = 0; k < b.count; ++k) {
        const float* row = b.vectors.data() + std::size_t(k) * std::size_t(b.dim);
        float mx = 0;
        for (int j = 0; j < b.dim; ++j) mx = std::max(mx, std::abs(row[j]));
        for (int j = 0; j < b.dim; ++j) {
            ++n.values;
            if (row[j] == 0.0f || std::abs(row[j]) <= thr * mx) {
                if (row[j] != 0.0f) ++n.dropped;
                continue;
            }
            acc.setValue(Coord(c, k, j), row[j]);
        }
    }
}

void getBasis(const openvdb::FloatGrid& g, int c, int dim, int count, PcaBasis& b) {
    auto acc = g.getConstAccessor();
    b.dim = dim;
    b.count = count;
    b.mean.resize(std::size_t(dim));
    b.vectors.assign(std::size_t(count) * std::size_t(dim), 0.0f);
    for (int j = 0; j < dim; ++j) b.mean[std::size_t(j)] = acc.getValue(Coord(c, -1, j));
    for (int k = 0; k < count; ++k)
        for (int j = 0; j < dim; ++j) b.vectors[std::size_t(k) * std::size_t(dim) + std::size_t(j)] = acc.getValue(Coord(c, k, j));
}

/// Names the grid and stores it as half floats if asked and every value fits.
template <typename GridT>
void finishGrid(GridT& grid, const std::string& name, bool quantize) {
    grid.setName(name);
    grid.setGridClass(openvdb::GRID_UNKNOWN);
    bool fits = true;
    for (auto it = grid.cbeginValueOn(); it && fits; ++it) {
        const auto v = *it;
        if constexpr (std::is_same_v<typename GridT::ValueType, float>) fits = std::abs(v) < kHalfMax;
        else fits = std::abs(v[0]) < kHalfMax && std::abs(v[1]) < kHalfMax && std::abs(v[2]) < kHalfMax;
    }
    grid.setSaveFloatAsHalf(quantize && fits);
    if constexpr (!std::is_same_v<typename GridT::ValueType, float>) grid.setVectorType(openvdb::VEC_INVARIANT);
}

/// The per-cluster transfer matrix rows (transferStride rows of the sample count each),
/// entries at or below the threshold of their row's largest dropped.
openvdb::Vec3SGrid::Ptr transferGrid(const PrtData& prt, float thr, Counter& n) {
    auto grid = openvdb::Vec3SGrid::create(openvdb::Vec3f(0.0f));
    auto acc = grid->getAccessor();
    const std::size_t ns = prt.samples.size();
    for (std::size_t c = 0; c < prt.samples.clusters(); ++c)
        for (int k = 0; k < prt.transferStride; ++k) {
            const Rgb* row = prt.transfer[c].data() + std::size_t(k) * ns;
            float mx = 0;
            for (std::size_t r = 0; r < ns; ++r)
                mx = std::max(mx, maxComponent(Rgb{std::abs(row[r].x), std::abs(row[r].y), std::abs(row[r].z)}));
            for (std::size_t r = 0; r < ns; ++r) {
                n.values += 3;
                const float a = std::max(std::abs(row[r].x), std::max(std::abs(row[r].y), std::abs(row[r].z)));
                if (a == 0.0f || a <= thr * mx) {
                    if (a != 0.0f) n.dropped += 3;
                    continue;
                }
                if (!isFinite(row[r])) throw ValueError("PRT data has non-finite transfer values");
                acc.setValue(Coord(int(c), k, int(r)), openvdb::Vec3f(row[r].x, row[r].y, row[r].z));
            }
        }
    return grid;
}

/// The volume transfer (9 SH coefficients per node of prt.volumeGrid), zeros left out.
openvdb::Vec3SGrid::Ptr volumeTransferGrid(const PrtData& prt, Counter& n) {
    auto grid = openvdb::Vec3SGrid::create(openvdb::Vec3f(0.0f));
    auto acc = grid->getAccessor();
    const std::size_t count = prt.volumeGrid.nodeCount() * 9;
    for (std::size_t c = 0; c < prt.samples.clusters(); ++c)
        for (int k = 0; k < prt.transferStride; ++k)
            for (std::size_t i = 0; i < count; ++i) {
                const Rgb& v = prt.volumeTransfer[c][std::size_t(k) * count + i];
                n.values += 3;
                if (v.x == 0.0f && v.y == 0.0f && v.z == 0.0f) continue;
                if (!isFinite(v)) throw ValueError("PRT data has non-finite volume transfer values");
                acc.setValue(Coord(int(c), k, int(i)), openvdb::Vec3f(v.x, v.y, v.z));
            }
    return grid;
}

/// Reads a (cluster, row, column) matrix grid into per-cluster row-major arrays of
/// `rows` x `columns`, refusing an entry outside them.
void readMatrix(const openvdb::Vec3SGrid& grid, std::size_t clusters, int rows, std::size_t columns,
                std::vector<std::vector<Rgb>>& out, const std::string& what, const std::string& path) {
    out.assign(clusters, std::vector<Rgb>(std::size_t(rows) * columns, Rgb{0, 0, 0}));
    for (auto it = grid.cbeginValueOn(); it; ++it) {
        const Coord xyz = it.getCoord();
        if (xyz.x() < 0 || std::size_t(xyz.x()) >= clusters || xyz.y() < 0 || xyz.y() >= rows || xyz.z() < 0 ||
            std::size_t(xyz.z()) >= columns)
            throw FormatError("'" + path + "' is not a valid PRT file: " + what + " entry out of range");
        const openvdb::Vec3f v = *it;
        out[std::size_t(xyz.x())][std::size_t(xyz.y()) * columns + std::size_t(xyz.z())] = Rgb{v[0], v[1], v[2]};
    }
}
}  // namespace

MatrixGrids writeMatrices(const PrtData& prt, const PrtWriteOptions& options, Counter& n) {
    MatrixGrids g;
    g.visBasis = openvdb::FloatGrid::create(0.0f);
    g.lightBasis = openvdb::FloatGrid::create(0.0f);
    for (std::size_t c = 0; c < prt.samples.clusters(); ++c) {
        putBasis(*g.visBasis, prt.visBasis[c], int(c), options.sparseThreshold, n);
        putBasis(*g.lightBasis, prt.lightBasis[c], int(c), options.sparseThreshold, n);
    }
    g.transfer = transferGrid(prt, options.sparseThreshold, n);
    if (prt.hasVolume()) {
        g.volumeTransfer = volumeTransferGrid(prt, n);
        finishGrid(*g.volumeTransfer, "prt_volume_transfer", options.quantize);
    }
    finishGrid(*g.visBasis, "prt_vis_basis", options.quantize);
    finishGrid(*g.lightBasis, "prt_light_basis", options.quantize);
    finishGrid(*g.transfer, "prt_transfer", options.quantize);
    return g;
}

void readMatrices(openvdb::io::File& file, PrtData& prt, const std::string& path) {
    const SurfaceSamples& s = prt.samples;
    const std::size_t n = s.size(), k = s.clusters();
    auto visBasis = requireGrid<openvdb::FloatGrid>(file, "prt_vis_basis", path);
    auto lightBasis = requireGrid<openvdb::FloatGrid>(file, "prt_light_basis", path);
    auto transfer = requireGrid<openvdb::Vec3SGrid>(file, "prt_transfer", path);
    const int d = prt.visGrid * prt.visGrid;
    prt.visBasis.resize(k);
    prt.lightBasis.resize(k);
    for (std::size_t c = 0; c < k; ++c) {
        const int nc = int(s.clusterBegin[c + 1] - s.clusterBegin[c]);
        getBasis(*visBasis, int(c), d, std::min({prt.visCoeffStride, nc, d}), prt.visBasis[c]);
        // The point lights' vectors (at most train_lights of them), then the one-sided ones.
        getBasis(*lightBasis, int(c), nc,
                 std::min({prt.transferStride - 1, int(prt.trainLights) + prt.orientedCoeffs, nc}), prt.lightBasis[c]);
    }
    readMatrix(*transfer, k, prt.transferStride, n, prt.transfer, "transfer", path);
    if (prt.volumeGrid.nodeCount() > 0) {  // the header read volume_dims
        auto volume = requireGrid<openvdb::Vec3SGrid>(file, "prt_volume_transfer", path);
        readMatrix(*volume, k, prt.transferStride, prt.volumeGrid.nodeCount() * 9, prt.volumeTransfer, "volume transfer",
                   path);
    }
}

}  // namespace vdblight::prt_io
