// Exports of a file rather than a volume in memory (export.h: intoOutputDirectory;
// export_cells.h: exportCellsOfFile), as `vdblight export` runs them.
#include <filesystem>

#include "vdblight/core/errors.h"
#include "vdblight/export/export.h"
#include "vdblight/query/query.h"
#include "vdblight/volume/vdb_io.h"

namespace vdblight {

void intoOutputDirectory(const std::string& outDir, const std::function<void()>& write) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const bool created = !fs::is_directory(outDir, ec);
    if (created && !fs::create_directories(outDir, ec))
        throw IoError("cannot create output directory '" + outDir + "'" + (ec ? ": " + ec.message() : ""));
    try {
        write();
    } catch (...) {
        if (created) fs::remove(outDir, ec);  // leave nothing behind
        throw;
    }
}

CellsSummary exportCellsOfFile(const std::string& path, const std::string& outDir, const ExportOptions& options,
                               int cellSize, uint64_t leafMemory) {
    std::error_code ec;
    const uint64_t bytes = std::filesystem::file_size(path, ec);
    if (!ec && bytes >= kStreamAboveBytes) {
        auto streamed = std::make_shared<StreamedVolume>(path);
        if (streamingSupported(*streamed).empty())
            return exportCells(makeStreamingQuery(streamed, OutsidePolicy::Clamp), *streamed, outDir, options, cellSize,
                               leafMemory);
    }
    const Volume volume = readVolume(path);
    return exportCells(IrradianceQuery(volume), volume, outDir, options, cellSize);
}

}  // namespace vdblight
