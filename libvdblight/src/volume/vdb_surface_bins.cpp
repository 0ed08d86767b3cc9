#include "vdb_surface_bins.h"

#include <cmath>
#include <memory>

#include "vdblight/errors.h"

namespace vdblight::vdb_detail {

namespace {
constexpr int kValues = SurfaceBinSums::kValuesPerBin;
constexpr int kGrids = SurfaceBinSums::kBinsPerCell * kValues;  // grid v: bin face v / 7, value v % 7
constexpr int kCountValue = 3;                                  // a bin's sample count
}  // namespace

void appendSurfaceBinGrids(const SurfaceBinSums& sums, const GridSpec& g, openvdb::GridCPtrVec& grids) {
    const std::array<int, 3> cells = SurfaceBinSums::cells(g);
    if (sums.values.size() != SurfaceBinSums::binCount(cells) * kValues)
        throw ValueError("the surface bins do not fit the volume's grid");
    for (int v = 0; v < kGrids; ++v) {
        const int face = v / kValues, value = v % kValues;
        openvdb::Int64Grid::Ptr grid = openvdb::Int64Grid::create(0);
        auto acc = grid->getAccessor();
        for (int k = 0; k < cells[2]; ++k)
            for (int j = 0; j < cells[1]; ++j)
                for (int i = 0; i < cells[0]; ++i) {
                    const uint64_t* bin = sums.values.data() + SurfaceBinSums::binIndex(cells, i, j, k, face) * kValues;
                    if (bin[kCountValue] == 0) continue;  // no samples
                    acc.setValue(openvdb::Coord(i, j, k), int64_t(bin[value]));
                }
        grid->setName(surfaceBinGridName(v));
        grid->setTransform(levelTransform(g));
        grid->setGridClass(openvdb::GRID_UNKNOWN);
        if (v == 0) grid->insertMeta(kPrefix + kSurfaceBinUnitKey, openvdb::DoubleMetadata(sums.unit));
        grids.push_back(grid);
    }
}

void readSurfaceBins(OpenedFile& f, Volume& volume, const std::string& path) {
    if (!f.file->hasGrid(surfaceBinGridName(0))) return;
    const GridSpec& g = volume.levels.at(0).grid;
    const std::array<int, 3> cells = SurfaceBinSums::cells(g);
    auto sums = std::make_shared<SurfaceBinSums>();
    sums->values.assign(SurfaceBinSums::binCount(cells) * kValues, 0);
    for (int v = 0; v < kGrids; ++v) {
        const std::string name = surfaceBinGridName(v);
        const openvdb::Int64Grid::Ptr grid = readPlacedInt64Grid(f, name, g, path);
        if (v == 0) {
            const auto unit = grid->getMetadata<openvdb::DoubleMetadata>(kPrefix + kSurfaceBinUnitKey);
            if (!unit || !(unit->value() > 0) || !std::isfinite(unit->value()))
                formatError(path, "grid '" + name + "' has no valid surface bin unit");
            sums->unit = unit->value();
        }
        const int face = v / kValues, value = v % kValues;
        for (auto it = grid->cbeginValueOn(); it; ++it) {
            const openvdb::Coord c = it.getCoord();
            if (c.x() < 0 || c.y() < 0 || c.z() < 0 || c.x() >= cells[0] || c.y() >= cells[1] || c.z() >= cells[2])
                formatError(path, "grid '" + name + "' has active voxels outside level 0's cells");
            sums->values[SurfaceBinSums::binIndex(cells, c.x(), c.y(), c.z(), face) * kValues + std::size_t(value)] =
                uint64_t(*it);
        }
    }
    volume.surfaceBins = std::move(sums);
}

}  // namespace vdblight::vdb_detail
