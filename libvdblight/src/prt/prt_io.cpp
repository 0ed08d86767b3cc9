// PRT files (docs/prt_format.md): writePrt and readPrt put together the file's
// three sections, header, samples and matrices (prt_io_sections.h, one file each).
#include "vdblight/prt/prt.h"

#include <cmath>
#include <filesystem>
#include <mutex>

#include "prt_io_sections.h"
#include "vdblight/core/atomic_file.h"
#include "volume/vdb_read_parts.h"

namespace vdblight {
namespace {

namespace fs = std::filesystem;
using prt_io::kP;
using prt_io::meta;

void initOpenVdb() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

struct Opened {
    std::unique_ptr<openvdb::io::File> file;
    openvdb::MetaMap::Ptr meta;
};

Opened openPrt(const std::string& path, bool requirePrt) {
    initOpenVdb();
    // The volume reader's checks first, with its messages ("no such file", "is a directory"):
    // OpenVDB trusts the lengths in the file.
    vdb_detail::checkReadable(path);
    vdb_detail::checkNotTruncated(path);
    Opened o;
    o.file = std::make_unique<openvdb::io::File>(path);
    try {
        o.file->open(false);
        o.meta = o.file->getMetadata();
    } catch (const std::exception& e) {
        throw FormatError("'" + path + "' is not a readable .vdb file: " + e.what());
    }
    auto kind = o.meta->getMetadata<openvdb::StringMetadata>(kP + "kind");
    if (requirePrt && (!kind || kind->value() != "prt")) {
        throw FormatError("'" + path + "' is not a PRT file (bake one with 'vdblight prt bake')");
    }
    return o;
}

}  // namespace

void writePrt(const PrtData& prt, const std::string& path, const PrtWriteOptions& options) {
    initOpenVdb();
    if (prt.samples.size() == 0) throw ValueError("PRT data has no samples");
    const fs::path parent = fs::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty() && !fs::is_directory(parent, ec)) {
        throw IoError("cannot write '" + path + "': directory '" + parent.string() + "' does not exist");
    }
    for (float v : prt.visCoeffs)
        if (!std::isfinite(v)) throw ValueError("PRT data has non-finite visibility coefficients");

    prt_io::Counter counted;
    counted.values = prt.visCoeffs.size();
    const prt_io::MatrixGrids matrices = prt_io::writeMatrices(prt, options, counted);
    const openvdb::MetaMap header = prt_io::writeHeader(prt, options, counted);
    openvdb::GridCPtrVec grids{prt_io::writeSamples(prt, options.quantize), matrices.visBasis, matrices.lightBasis,
                               matrices.transfer};
    if (matrices.volumeTransfer) grids.push_back(matrices.volumeTransfer);
    writeFileAtomically(path, [&](const std::string& temp) { openvdb::io::File(temp).write(grids, header); });
}

bool isPrtFile(const std::string& path) {
    Opened o = openPrt(path, false);
    auto kind = o.meta->getMetadata<openvdb::StringMetadata>(kP + "kind");
    return kind && kind->value() == "prt";
}

PrtData readPrt(const std::string& path) {
    Opened o = openPrt(path, true);
    PrtData prt = prt_io::readHeader(*o.meta, path);
    prt_io::readSamples(*o.file, prt, path);
    prt_io::readMatrices(*o.file, prt, path);
    prepareRelight(prt);
    return prt;
}

PrtFileInfo inspectPrt(const std::string& path) {
    Opened o = openPrt(path, true);
    const openvdb::MetaMap& m = *o.meta;
    PrtFileInfo info;
    info.fileBytes = uint64_t(fs::file_size(path));
    info.samples = uint64_t(meta<int64_t>(m, "samples", path));
    info.clusters = uint64_t(meta<int64_t>(m, "clusters", path));
    info.values = uint64_t(meta<int64_t>(m, "values", path));
    info.droppedValues = uint64_t(meta<int64_t>(m, "dropped_values", path));
    info.bytesFloat32 = info.values * 4;
    uint64_t stored = 0;
    for (const char* name : {"prt_vis_basis", "prt_light_basis", "prt_transfer", "prt_volume_transfer"}) {
        if (!o.file->hasGrid(name)) continue;
        auto g = o.file->readGrid(name);
        const uint64_t channels = std::string(name).find("transfer") != std::string::npos ? 3 : 1;
        stored += g->activeVoxelCount() * channels * (g->saveFloatAsHalf() ? 2 : 4);
    }
    const uint64_t visValues = info.samples * uint64_t(meta<int64_t>(m, "vis_coeffs", path));
    stored += visValues * (meta<bool>(m, "quantized", path) ? 2 : 4);
    info.bytesStored = stored;
    return info;
}

}  // namespace vdblight
