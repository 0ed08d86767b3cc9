#include "vdb_surface_bins.h"

#include <array>
#include <cmath>
#include <map>
#include <memory>

#include "vdblight/core/errors.h"

namespace vdblight::vdb_detail {

namespace {
constexpr int kValues = SurfaceBinSums::kValuesPerBin;
constexpr int kGrids = SurfaceBinSums::kBinsPerCell * kValues;  // grid v: bin face v / 7, value v % 7
constexpr int kCountValue = 3;                                  // a bin's sample count
}  // namespace

void appendSurfaceBinGrids(const SurfaceBinSums& sums, const GridSpec& g, openvdb::GridCPtrVec& grids) {
    const std::array<int, 3> cells = SurfaceBinSums::cells(g);
    sums.validate(cells);
    for (int v = 0; v < kGrids; ++v) {
        const int face = v / kValues, value = v % kValues;
        openvdb::Int64Grid::Ptr grid = openvdb::Int64Grid::create(0);
        auto acc = grid->getAccessor();
        for (std::size_t c = 0; c < sums.cellIndices.size(); ++c) {
            const uint64_t* bin = sums.values.data() + c * SurfaceBinSums::kValuesPerCell + std::size_t(face) * kValues;
            if (bin[kCountValue] == 0) continue;  // no samples
            const std::array<int, 3> ijk = SurfaceBinSums::cellCoord(cells, sums.cellIndices[c]);
            acc.setValue(openvdb::Coord(ijk[0], ijk[1], ijk[2]), int64_t(bin[value]));
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
    // Cells in ascending linear order (the sums' order), whatever order the grids iterate in.
    std::map<uint64_t, std::array<uint64_t, SurfaceBinSums::kValuesPerCell>> byCell;
    for (int v = 0; v < kGrids; ++v) {
        const std::string name = surfaceBinGridName(v);
        const openvdb::Int64Grid::Ptr grid = readPlacedInt64Grid(f, name, g, path);
        if (v == 0) {
            const auto unit = grid->getMetadata<openvdb::DoubleMetadata>(kPrefix + kSurfaceBinUnitKey);
            if (!unit || !(unit->value() > 0) || !std::isfinite(unit->value()))
                formatError(path, "grid '" + name + "' has no valid surface bin unit");
            sums->unit = unit->value();
        }
        for (auto it = grid->cbeginValueOn(); it; ++it) {
            const openvdb::Coord c = it.getCoord();
            if (c.x() < 0 || c.y() < 0 || c.z() < 0 || c.x() >= cells[0] || c.y() >= cells[1] || c.z() >= cells[2])
                formatError(path, "grid '" + name + "' has active voxels outside level 0's cells");
            auto slot = byCell.try_emplace(SurfaceBinSums::cellIndex(cells, c.x(), c.y(), c.z())).first;
            slot->second[std::size_t(v)] = uint64_t(*it);  // grid v: bin face v / 7, value v % 7
        }
    }
    sums->cellIndices.reserve(byCell.size());
    sums->values.reserve(byCell.size() * SurfaceBinSums::kValuesPerCell);
    for (const auto& [index, cellValues] : byCell) {
        sums->cellIndices.push_back(index);
        sums->values.insert(sums->values.end(), cellValues.begin(), cellValues.end());
    }
    volume.surfaceBins = std::move(sums);
}

}  // namespace vdblight::vdb_detail
