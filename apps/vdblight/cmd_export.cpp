// vdblight export VOLUME -o OUTDIR: dense 3-D textures + manifest.json for game engines.
#include <filesystem>
#include <iostream>

#include "app_common.h"
#include "commands.h"
#include "vdblight/errors.h"
#include "vdblight/export.h"
#include "vdblight/export_cells.h"
#include "vdblight/query_stream.h"
#include "vdblight/vdb_stream.h"
#include "vdblight/preview.h"
#include "vdblight/vdb_io.h"

namespace vdblight::app {

namespace {
struct ExportCommand {
    std::string volume;
    std::string output;
    std::string format = "ktx2";
    std::string layout = "sh2-packed";
    bool half = false, full = false;
    int resolution = 0;
    bool quiet = false;
    int cells = 0;  // lattice steps per streaming cell (export_cells.h); 0: one texture set
    double leafMemoryMiB = double(kCellsLeafMemory >> 20);  // --cells of a streamed volume: leaves kept between releases
};

/// export --cells K: the volume streamed when it is large and its kind streams (as `query`
/// does), read whole otherwise; the same texels either way.
CellsSummary exportByCells(const ExportCommand& c, const ExportOptions& o) {
    std::error_code ec;
    const uint64_t bytes = std::filesystem::file_size(c.volume, ec);
    if (!ec && bytes >= kStreamAboveBytes) {
        auto streamed = std::make_shared<StreamedVolume>(c.volume);
        if (streamingSupported(*streamed).empty())
            return exportCells(makeStreamingQuery(streamed, OutsidePolicy::Clamp), *streamed, c.output, o, c.cells,
                               uint64_t(c.leafMemoryMiB * double(1 << 20)));
    }
    const Volume volume = readVolume(c.volume);
    return exportCells(IrradianceQuery(volume), volume, c.output, o, c.cells);
}

void run(const ExportCommand& c) {
    if (c.half && c.full) throw ValueError("give --half or --float, not both");
    if (c.format == "vdb-preview") {  // preview grids for Blender / Houdini (preview.h)
        namespace fs = std::filesystem;
        const Volume volume = readVolume(c.volume);
        std::error_code ec;
        const bool created = !fs::is_directory(c.output, ec);
        if (created && !fs::create_directories(c.output, ec))
            throw IoError("cannot create output directory '" + c.output + "'" + (ec ? ": " + ec.message() : ""));
        const std::string file = (fs::path(c.output) / "preview.vdb").string();
        TextureLattice l;
        try {
            l = exportPreviewVdb(volume, file, c.resolution);
        } catch (...) {
            if (created) fs::remove(c.output, ec);  // leave nothing behind
            throw;
        }
        if (!c.quiet)
            std::cout << "Wrote preview grids (irradiance_avg, irradiance_<axis><pos|neg>, density) of " << l.dims[0]
                      << " x " << l.dims[1] << " x " << l.dims[2] << " voxels to " << file << "\n";
        return;
    }
    ExportOptions o;
    o.format = parseTextureFormat(c.format);
    o.layout = parseExportLayout(c.layout);
    o.halfFloat = !c.full;
    o.resolution = c.resolution;
    if (c.cells != 0) {
        const CellsSummary s = exportByCells(c, o);
        if (!c.quiet)
            std::cout << "Exported " << s.cells[0] << " x " << s.cells[1] << " x " << s.cells[2] << " cells of "
                      << formatName(o.format) << " textures (" << layoutName(o.layout) << ", "
                      << (o.halfFloat ? "half" : "float") << ") over " << s.lattice.dims[0] << " x " << s.lattice.dims[1]
                      << " x " << s.lattice.dims[2] << " texels + cells.json to " << c.output << " ("
                      << formatBytes(double(s.bytes)) << ")\n";
        return;
    }
    const Volume volume = readVolume(c.volume);
    const ExportSummary s = exportTextures(volume, c.output, o);
    if (!c.quiet)
        std::cout << "Exported " << s.files.size() - 1 << " " << formatName(o.format) << " textures ("
                  << layoutName(o.layout) << ", " << (o.halfFloat ? "half" : "float") << ") of "
                  << s.lattice.dims[0] << " x " << s.lattice.dims[1] << " x " << s.lattice.dims[2]
                  << " texels + manifest.json to " << c.output << " (" << formatBytes(double(s.bytes)) << ")\n";
}
}  // namespace

void addExportCommand(CLI::App& app) {
    auto c = std::make_shared<ExportCommand>();
    CLI::App* cmd = app.add_subcommand("export", "Dense 3-D textures + manifest.json for engines (docs/engines.md)");
    cmd->add_option("volume", c->volume, "Volume (.vdb) written by vdblight bake")->required();
    cmd->add_option("-o,--output", c->output, "Output directory (created if missing)")->required();
    cmd->add_option("--format", c->format, "ktx2, dds, exr-atlas, raw, or vdb-preview (OUTDIR/preview.vdb for Blender/Houdini)")->capture_default_str();
    cmd->add_option("--layout", c->layout, "SH volumes: sh2 (9 coefficient textures), sh2-packed (7, dot-product ready) or sh1 (3); irradiance-vector volumes: vectors (18) or compact (12); bins:R / moment:n volumes: bins (2 R^2); any registered basis (sh2, sh:N, bins, moment; vdblight bake --help): basis (its own textures, one per channel)")
        ->capture_default_str();
    cmd->add_flag("--half", c->half, "16-bit float texels (the default)");
    cmd->add_flag("--float", c->full, "32-bit float texels");
    cmd->add_option("--resolution", c->resolution,
                    "Texels along the longest axis (default: the volume's finest node spacing)");
    cmd->add_option("--cells", c->cells,
                    "Cut the textures into streaming cells of K lattice steps per edge: OUTDIR/cell_<a>_<b>_<c>/ with "
                    "textures + manifest.json each and OUTDIR/cells.json as index; neighbours share a texel plane "
                    "(SH layouts and basis, with the light visibility and depth textures; large volumes are streamed, not read whole)")
        ->check(CLI::Range(1, 1 << 20));
    cmd->add_option("--cells-leaf-memory", c->leafMemoryMiB,
                    "--cells of a volume large enough to be streamed (256 MiB and more): MiB of leaves read that are "
                    "kept in memory between cells before they are dropped")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_flag("-q,--quiet", c->quiet, "Print nothing on success");
    cmd->callback([c] { run(*c); });
}

}  // namespace vdblight::app
