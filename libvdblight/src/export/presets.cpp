// exportPreset (export_engines.h): one engine's format, layout, axes, units and file split.
//   unity  - EXR atlases (Texture Shape 3D import), sh2-packed, left-handed +Y up, metres
//   godot  - EXR atlases (Texture3D import, slices), sh2-packed, +Y up, metres
//   unreal - .vdb Sparse Volume Textures, sh2-packed, 2 RGBA textures per file, +Z up, cm
//   bevy   - the IrradianceVolume KTX2 (bevy_volume.cpp)
//   three  - export --format three: three.js LightProbeGridWebGL's SH atlas + probe_grid.json (export_three.h)
#include <cmath>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "engine_internal.h"
#include "fold_direct.h"
#include "staged_files.h"
#include "vdblight/basis/bins.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/engines.h"
#include "basis/sh.h"

namespace vdblight {

using namespace exporter;

EnginePreset parseEnginePreset(const std::string& name) {
    for (EnginePreset p : {EnginePreset::Unity, EnginePreset::Unreal, EnginePreset::Godot, EnginePreset::Three,
                           EnginePreset::Bevy})
        if (name == presetName(p)) return p;
    throw ValueError("unknown preset '" + name + "' (choose unity, unreal, godot, three or bevy)");
}

const char* presetName(EnginePreset p) {
    switch (p) {
        case EnginePreset::Unity: return "unity";
        case EnginePreset::Unreal: return "unreal";
        case EnginePreset::Godot: return "godot";
        case EnginePreset::Three: return "three";
        case EnginePreset::Bevy: return "bevy";
    }
    return "";
}

namespace {

// The preset manifests are built as JSON objects whose keys keep the order they are added in.
using Json = nlohmann::ordered_json;

Json vec(const Vec3d& v) { return Json::array({v.x, v.y, v.z}); }

// The SH presets read the order-2 projection of the volume (sh2-packed): SH volumes of order
// 2 or more only; other kinds would need a refit that these engines' shaders do not undo.
void checkShVolume(const Volume& volume, EnginePreset preset) {
    bins::BasisSpec spec;
    const std::unique_ptr<Basis> basis = basisOf(volume.basis);
    if (!basis || bins::specFromVolume(volume.basis, spec) || basis->shCoefficients() < sh::kCoeffs)
        throw FormatError(std::string("preset '") + presetName(preset) + "' writes SH order-2 textures and needs an SH "
                          "volume (sh2 or sh:N, N >= 2); this one stores '" + volume.basis.kind +
                          "' (--preset bevy takes every kind)");
    // The presets' textures are the SH alone: an occlusion volume's listed lights are folded
    // into it (fold_direct.h); a runtime volume's lights need the scene's shadows at run time,
    // which the SH cannot hold, so it is refused rather than exported dim.
    if (volume.direct.mode == DirectMode::Runtime && !volume.direct.lights.empty())
        throw FormatError(std::string("preset '") + presetName(preset) + "' writes the SH only, but this volume keeps the "
                          "direct light of " + std::to_string(volume.direct.lights.size()) + " light(s) for the run time "
                          "to add (bake --direct runtime); bake with --direct occlusion (folded on export) or --direct "
                          "baked, or export --layout sh2-packed with docs/engines.md's direct-light shader");
}

std::string presetManifest(EnginePreset preset, const EngineFrame& f, const TextureLattice& e,
                           const std::vector<TextureDesc>& descs, const std::vector<std::string>& textureFiles,
                           const std::vector<SvtFile>& svt, const Json& foldedDirect) {
    const Vec3d h = e.spacing();
    Json m;
    m["vdblight_export_version"] = 2;
    m["preset"] = presetName(preset);
    m["engine_frame"] = f.description;
    m["from_volume"] = "engine[a] = " + jsonNumber(f.metresToUnit) +
                       " * sign[a] * volume[axis[a]] (the volume: right-handed, +Y up, metres); normals the same without "
                       "the scale";
    m["axis"] = {f.axis[0], f.axis[1], f.axis[2]};
    m["sign"] = {f.sign[0], f.sign[1], f.sign[2]};
    m["units_per_metre"] = f.metresToUnit;
    m["layout"] = "sh2-packed";
    m["formula"] = "E_c = dot(shAc, (n, 1)) + dot(shBc, (n.x*n.y, n.y*n.z, n.z*n.z, n.z*n.x)) + shC.c * (n.x*n.x - "
                   "n.y*n.y), n a unit normal in the engine's axes";
    m["irradiance_units"] = "W/m^2 per colour channel (the scene's unit; per square metre whatever the length unit); a "
                            "Lambertian surface of albedo rho leaves rho E / pi";
    m["dims"] = {e.dims[0], e.dims[1], e.dims[2]};
    m["bounds_min"] = vec(e.lo);
    m["bounds_max"] = vec(e.hi);
    m["texel_spacing"] = vec(h);
    if (!foldedDirect.is_null()) m["direct_light"] = foldedDirect;
    Vec3d scale, bias;
    for (int a = 0; a < 3; ++a) {
        scale[a] = h[a] > 0 ? 1.0 / (h[a] * e.dims[a]) : 0.0;
        bias[a] = h[a] > 0 ? (0.5 - e.lo[a] / h[a]) / e.dims[a] : 0.5;
    }
    m["uvw_scale"] = vec(scale);
    m["uvw_bias"] = vec(bias);
    if (!textureFiles.empty()) {
        const AtlasGrid g = atlasGrid(e.dims[2]);
        m["exr_atlas"] = {{"columns", g.columns}, {"rows", g.rows}, {"slice_width", e.dims[0]},
                          {"slice_height", e.dims[1]}, {"slices", e.dims[2]}};
    }
    Json textures = Json::array();
    for (std::size_t t = 0; t < descs.size(); ++t) {
        std::string file;
        for (const SvtFile& sf : svt)
            for (const std::string& name : sf.textures)
                if (name == descs[t].name) file = sf.file;
        if (!textureFiles.empty()) file = textureFiles[t];
        textures.push_back({{"name", descs[t].name}, {"file", file}, {"components", descs[t].components}});
    }
    m["textures"] = std::move(textures);
    if (!svt.empty()) {
        Json files = Json::array();
        for (const SvtFile& sf : svt) {
            Json entry;
            entry["file"] = sf.file;
            for (std::size_t t = 0; t < sf.textures.size(); ++t) {  // attribute A, then B
                const std::string& name = sf.textures[t];
                std::string attribute = name + "_rgb (RGB)";
                for (const std::string& g : sf.grids)
                    if (g == name + "_a") attribute += " + " + g + " (A)";
                entry[std::string("attribute_") + "ab"[t]] = attribute;
            }
            entry["grids"] = sf.grids;
            entry["precision"] = "half";
            files.push_back(std::move(entry));
        }
        m["svt_files"] = std::move(files);
    }
    return m.dump(2) + "\n";
}

}  // namespace

PresetSummary exportPreset(const Volume& volume, const std::string& outDir, EnginePreset preset, int resolution) {
    if (preset == EnginePreset::Bevy) return exportBevyIrradianceVolume(volume, outDir, resolution);
    if (preset == EnginePreset::Three) {  // three.js LightProbeGridWebGL: the atlas of export --format three
        ThreeGridOptions t;
        t.resolution = resolution;
        const ThreeGridSummary g = exportThreeGrid(volume, outDir, t);
        PresetSummary s;
        s.lattice = g.lattice;
        s.files = g.files;
        s.bytes = g.bytes;
        s.foldedLights = g.foldedLights;
        return s;
    }
    if (outDir.empty()) throw IoError("no output directory given");
    checkShVolume(volume, preset);
    const EngineFrame frame = engineFrame(preset);
    const IrradianceQuery query(volume);
    const TextureLattice lattice = chooseLattice(query.bounds(), finestSpacing(volume.levels), resolution);
    const TextureLattice engine = engineLattice(frame, lattice);
    const bool svt = preset == EnginePreset::Unreal;
    if (!svt) {
        const AtlasGrid g = atlasGrid(engine.dims[2]);
        if (1LL * g.columns * engine.dims[0] > 16384 || 1LL * g.rows * engine.dims[1] > 16384)
            throw ValueError("the EXR atlas would exceed the 16384-pixel 2-D texture limit of the engine; lower --resolution");
    }
    if (lattice.texelCount() > (1ull << 28))
        throw ValueError("the preset's textures would have over 2^28 texels; lower --resolution");
    const std::vector<TextureDesc> descs = layoutTextures(ExportLayout::Sh2Packed);
    std::vector<std::vector<float>> sampled = sampleLayout(query, lattice, ExportLayout::Sh2Packed);
    addFoldedDirectLight(volume, query, lattice, ExportLayout::Sh2Packed, sampled);  // occlusion volumes (fold_direct.h)
    std::vector<std::vector<float>> textures = reorientSh2Packed(frame, lattice, sampled);
    for (const std::vector<float>& t : textures)
        for (float v : t)
            if (!(std::fabs(v) <= 65504.0f))
                throw ValueError("a texel holds " + std::to_string(v) + ", outside the half-float range of the preset's "
                                 "textures (+-65504)");

    PresetSummary summary;
    summary.lattice = engine;
    StagedFiles staged;
    staged.createDirectory(outDir);
    std::vector<std::string> textureFiles;
    std::vector<SvtFile> svtFiles;
    if (svt) {
        svtFiles = planSvtFiles(descs);
        for (const SvtFile& f : svtFiles)
            writeSvtFile(staged.stage(outDir, f.file), f, descs, textures, engine,
                         finestSpacing(volume.levels) * frame.metresToUnit);
    } else {
        for (std::size_t t = 0; t < descs.size(); ++t) {
            TextureImage image;
            image.rgba = textures[t].data();
            std::copy_n(engine.dims, 3, image.dims);
            image.format = TexelFormat::Float16;
            image.name = descs[t].name;
            textureFiles.push_back(descs[t].name + ".exr");
            writeExrAtlas(staged.stage(outDir, textureFiles.back()), image);
        }
    }
    const bool folds = foldsDirectLight(volume);
    const std::string json =
        presetManifest(preset, frame, engine, descs, textureFiles, svtFiles, folds ? foldedDirectJson(volume) : Json());
    writeBytes(staged.stage(outDir, "manifest.json"), std::vector<uint8_t>(json.begin(), json.end()));
    summary.files = staged.commit();
    for (const std::string& f : summary.files) summary.bytes += std::filesystem::file_size(f);
    if (folds) summary.foldedLights = int(volume.direct.lights.size());
    return summary;
}

}  // namespace vdblight
