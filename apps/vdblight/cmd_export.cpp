// vdblight export VOLUME -o OUTDIR: dense 3-D textures + manifest.json for game engines.
#include <filesystem>
#include <iostream>

#include "app_common.h"
#include "commands.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/export.h"
#include "vdblight/export/engines.h"
#include "vdblight/export/slice.h"
#include "vdblight/volume/vdb_io.h"

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
    std::string preset;  // unity | unreal | godot | three | bevy (export_engines.h)
    int every = 0;       // --format gltf: every K-th node per axis
    std::string slice;   // --format gltf: AXIS=VALUE
    double probeRadius = 0;
    double leafMemoryMiB = double(kCellsLeafMemory >> 20);  // --cells of a streamed volume: leaves kept between releases
};

/// export --format gltf: OUTDIR/probes.glb (export_gltf.h).
void runGltf(const ExportCommand& c) {
    GltfProbeOptions o;
    o.every = c.every;
    o.radius = c.probeRadius;
    if (!c.slice.empty()) {
        const std::size_t eq = c.slice.find('=');
        const std::string axis = c.slice.substr(0, eq);
        if (eq == std::string::npos || axis.size() != 1 || std::string("xyz").find(axis) == std::string::npos)
            throw ValueError("--slice takes AXIS=VALUE, e.g. y=1.2 (got '" + c.slice + "')");
        o.sliceAxis = int(std::string("xyz").find(axis));
        try {
            o.sliceAt = std::stod(c.slice.substr(eq + 1));
        } catch (const std::exception&) {
            throw ValueError("--slice takes AXIS=VALUE, e.g. y=1.2 (got '" + c.slice + "')");
        }
    }
    const Volume volume = readVolume(c.volume);
    const std::string file = (std::filesystem::path(c.output) / "probes.glb").string();
    GltfProbeSummary s;
    intoOutputDirectory(c.output, [&] { s = exportGltfProbes(volume, file, o); });
    if (!c.quiet)
        std::cout << "Wrote " << s.spheres << " probe spheres (vertex colour = " << s.colourScale
                  << " * E(n) / pi) and the volume's box to " << file << " (" << formatBytes(double(s.bytes)) << ")\n";
}

void runPreset(const ExportCommand& c) {
    const EnginePreset preset = parseEnginePreset(c.preset);
    const PresetSummary s = exportPreset(readVolume(c.volume), c.output, preset, c.resolution);
    if (!c.quiet)
        std::cout << "Exported preset " << presetName(preset) << ": " << s.files.size() - 1 << " files of "
                  << s.lattice.dims[0] << " x " << s.lattice.dims[1] << " x " << s.lattice.dims[2]
                  << " voxels + manifest.json to " << c.output << " (" << formatBytes(double(s.bytes)) << ")\n";
    if (!c.quiet && s.foldedLights > 0)
        std::cout << "Folded the direct light of " << s.foldedLights << " light(s) (bake --direct occlusion) into the SH\n";
}

void run(const ExportCommand& c) {
    if (c.half && c.full) throw ValueError("give --half or --float, not both");
    if (!c.preset.empty()) return runPreset(c);
    if (c.format == "gltf") return runGltf(c);
    if (c.format == "vdb-preview") {  // preview grids for Blender / Houdini (preview.h)
        const Volume volume = readVolume(c.volume);
        const std::string file = (std::filesystem::path(c.output) / "preview.vdb").string();
        TextureLattice l;
        intoOutputDirectory(c.output, [&] { l = exportPreviewVdb(volume, file, c.resolution); });
        if (!c.quiet)
            std::cout << "Wrote preview grids (irradiance_avg, irradiance_<axis><pos|neg>, density) of " << l.dims[0]
                      << " x " << l.dims[1] << " x " << l.dims[2] << " voxels to " << file << "\n";
        return;
    }
    if (c.format == "nanovdb") {  // one .nvdb file of NanoVDB grids (export_nanovdb.h)
        const NanoVdbSummary s = exportNanoVdb(readVolume(c.volume), c.output);
        if (!c.quiet)
            std::cout << "Wrote " << s.grids.size() << " NanoVDB grids (" << s.activeNodes << " nodes, "
                      << formatBytes(double(s.bytes)) << ") to " << c.output << "\n";
        return;
    }
    if (c.format == "three") {  // three.js LightProbeGridWebGL atlas + probe_grid.json (export_three.h)
        if (c.cells != 0) throw ValueError("--cells does not apply to --format three (one probe grid)");
        ThreeGridOptions t;
        t.halfFloat = !c.full;
        t.resolution = c.resolution;
        const ThreeGridSummary s = exportThreeGrid(readVolume(c.volume), c.output, t);
        if (!c.quiet)
            std::cout << "Exported a three.js LightProbeGridWebGL grid of " << s.lattice.dims[0] << " x "
                      << s.lattice.dims[1] << " x " << s.lattice.dims[2] << " probes (" << (t.halfFloat ? "half" : "float")
                      << " atlas " << s.lattice.dims[0] << " x " << s.lattice.dims[1] << " x " << s.atlasDepth
                      << ") + " << kThreeGridJsonFile << " to " << c.output << " (" << formatBytes(double(s.bytes)) << ")\n";
        if (!c.quiet && s.foldedLights > 0)
            std::cout << "Folded the direct light of " << s.foldedLights << " light(s) (bake --direct occlusion) into the SH\n";
        return;
    }
    ExportOptions o;
    o.format = parseTextureFormat(c.format);
    o.layout = parseExportLayout(c.layout);
    o.halfFloat = !c.full;
    o.resolution = c.resolution;
    if (c.cells != 0) {
        const CellsSummary s = exportCellsOfFile(c.volume, c.output, o, c.cells, uint64_t(c.leafMemoryMiB * double(1 << 20)));
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
    cmd->add_option("--format", c->format, "ktx2, dds, exr-atlas, raw, vdb-preview (OUTDIR/preview.vdb for Blender/Houdini), nanovdb (-o names one .nvdb file), three (three.js LightProbeGridWebGL: OUTDIR/probe_grid_sh.bin + probe_grid.json; SH volumes, --layout ignored) or gltf (OUTDIR/probes.glb: a sphere per node)")->capture_default_str();
    cmd->add_option("--layout", c->layout, "SH volumes: sh2 (9 coefficient textures), sh2-packed (7, dot-product ready), sh1 (3), sh2-32 (7, 32 B per probe: L0 half, the rest / L0 in 8 bits) or sh1-16 (3, 16 B); irradiance-vector volumes: vectors (18) or compact (12); bins:R / moment:n volumes: bins (2 R^2); any registered basis (sh2, sh:N, bins, moment; vdblight bake --help): basis (its own textures, one per channel)")
        ->capture_default_str();
    cmd->add_flag("--half", c->half, "16-bit float texels (the default)");
    cmd->add_flag("--float", c->full, "32-bit float texels");
    cmd->add_option("--resolution", c->resolution,
                    "Texels along the longest axis (default: the volume's finest node spacing)");
    cmd->add_option("--cells", c->cells,
                    "Cut the textures into streaming cells of K lattice steps per edge: OUTDIR/cell_<a>_<b>_<c>/ with "
                    "textures + manifest.json each and OUTDIR/cells.json as index; neighbours share a texel plane "
                    "(SH layouts and basis, with the light visibility, shadow-edge and depth textures; large volumes are "
                    "streamed, not read whole)")
        ->check(CLI::Range(1, 1 << 20));
    cmd->add_option("--preset", c->preset,
                    "Everything one engine needs (format, layout, axes, units, file split; docs/engines.md): unity, "
                    "unreal, godot, three or bevy (overrides --format and --layout)");
    cmd->add_option("--every", c->every, "--format gltf: a sphere at every K-th node along each axis")
        ->check(CLI::Range(1, 1 << 20));
    cmd->add_option("--slice", c->slice, "--format gltf: only the nodes on the plane AXIS=VALUE (e.g. y=1.2)");
    cmd->add_option("--probe-radius", c->probeRadius, "--format gltf: sphere radius (default 0.2 node spacings)");
    cmd->add_option("--cells-leaf-memory", c->leafMemoryMiB,
                    "--cells of a volume large enough to be streamed (256 MiB and more): MiB of leaves read that are "
                    "kept in memory between cells before they are dropped")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_flag("-q,--quiet", c->quiet, "Print nothing on success");
    cmd->callback([c] { run(*c); });
}

}  // namespace vdblight::app
