// Pieces of the engine presets shared between their files (not public API).
#pragma once

#include <string>
#include <vector>

#include "export_internal.h"
#include "vdblight/export/engines.h"

namespace vdblight::exporter {

/// The volume's texel lattice seen in an engine frame: texel (e0, e1, e2) of the engine
/// lattice is texel volumeTexel(...) of the volume lattice; bounds in engine units.
TextureLattice engineLattice(const EngineFrame& frame, const TextureLattice& volume);
/// The volume texel holding engine texel (e0, e1, e2).
void volumeTexel(const EngineFrame& frame, const TextureLattice& volume, const int engine[3], int out[3]);

/// The seven sh2-packed textures of the volume lattice rewritten for the engine frame: texels
/// reordered onto the engine lattice and each colour's quadratic form E(n) = c + b.n + n'Qn
/// expressed in the engine's axes (n_engine[a] = sign[a] n_volume[axis[a]]), then packed again.
std::vector<std::vector<float>> reorientSh2Packed(const EngineFrame& frame, const TextureLattice& volume,
                                                  const std::vector<std::vector<float>>& textures);

/// Writes the Unreal Sparse Volume Texture files: 2 textures (8 channels) per .vdb, each
/// texture as a half Vec3 grid <name>_rgb and, unless its alpha is always 0, a half float
/// grid <name>_a. Returns each file's name and the grids it holds, for the manifest.
struct SvtFile {
    std::string file;
    std::vector<std::string> textures, grids;
};
std::vector<SvtFile> planSvtFiles(const std::vector<TextureDesc>& descs);
void writeSvtFile(const std::string& path, const SvtFile& plan, const std::vector<TextureDesc>& descs,
                  const std::vector<std::vector<float>>& textures, const TextureLattice& lattice, double finestUnits);

/// A number as "%.17g" text (it reads back as the same double), for a number
/// quoted inside prose (the preset manifests' from_volume).
std::string jsonNumber(double v);

}  // namespace vdblight::exporter
