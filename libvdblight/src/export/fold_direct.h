// Folding an occlusion volume's direct light into its SH for SH-only engines (internal to the
// export module).
//
// `bake --direct occlusion` (the default) keeps the chosen lights' direct light out of the SH:
// the query adds exactIrradiance x interpolated visibility at lookup (query_direct.h). Engines
// that run only an SH shader (three.js's LightProbeGridWebGL, the unity / godot / unreal
// presets) cannot add it, so export adds to every texel the SH order-2 radiance coefficients
// whose irradiance best fits that direct term at the texel point: E_direct(x, n) from
// OcclusionLookup::direct for a fixed set of normals, fitted by least squares onto bands 0..2
// as irradiance, band l divided by A_l (docs/format.md). What the engine then loses is the
// part of the clamped cosine beyond band 2 (Ramamoorthi & Hanrahan): for a point light, 0.8 %
// of the lobe's energy and at most 3/32 of the light's peak irradiance at any normal.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "export_internal.h"

namespace vdblight::exporter {

/// Number of normals of the fixed quadrature (a spherical Fibonacci set).
constexpr int kFoldNormals = 128;

/// The i-th normal of the set (i < kFoldNormals), as the float the lookup is given.
Vec3f foldNormal(int i);

/// The nine RGB radiance coefficients (docs/format.md) that the direct light of the lights
/// listed by an occlusion volume adds at x, as the query computes it (OcclusionLookup::direct):
/// its least-squares SH order-2 irradiance fit over the kFoldNormals normals, band l divided
/// by A_l. All zero where no listed light reaches x. `query` must wrap an OcclusionLookup
/// (FormatError otherwise).
void foldedDirectRadiance(const IrradianceQuery& query, const Vec3d& x, Rgb out[9]);

/// True if export must fold: the volume keeps listed lights' direct light outside the SH with
/// visibility channels (--direct occlusion with lights).
bool foldsDirectLight(const Volume& volume);

/// Adds the folded direct light to textures sampled by sampleLayout(query, lattice, layout)
/// for layout sh2 or sh2-packed (both linear in the coefficients): every texel gets
/// packTexel(layout, foldedDirectRadiance(x)) added. Texels where the fold is zero are left
/// untouched (bit for bit); so is everything when the volume folds nothing.
void addFoldedDirectLight(const Volume& volume, const IrradianceQuery& query, const TextureLattice& lattice,
                          ExportLayout layout, std::vector<std::vector<float>>& textures);

/// The JSON value stating what was folded (for manifest.json and probe_grid.json): an object
/// with the method and the lights (formatDirectLight text, docs/format.md).
nlohmann::ordered_json foldedDirectJson(const Volume& volume);

}  // namespace vdblight::exporter
