// Pieces of the export module shared between its files (not public API).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "vdblight/basis/basis.h"
#include "vdblight/export/export.h"
#include "vdblight/query/query.h"
#include "basis/sh.h"

namespace vdblight::exporter {

// Real SH constants (docs/format.md "SH convention") and the cosine-lobe factors A_l, for
// the layouts that pack SH terms (layouts.cpp, compact_sh.cpp).
inline const double kC0 = 0.5 / std::sqrt(kPi);           // Y_0
inline const double kC1 = std::sqrt(3.0 / (4.0 * kPi));   // Y_1..3 / (y, z, x)
inline const double kC2 = std::sqrt(15.0 / (4.0 * kPi));  // Y_4, Y_5, Y_7 / (xy, yz, xz)
inline const double kC3 = std::sqrt(5.0 / (16.0 * kPi));  // Y_6 / (3 z^2 - 1)
inline const double kC4 = std::sqrt(15.0 / (16.0 * kPi)); // Y_8 / (x^2 - y^2)
inline const double kA0 = sh::kCosineLobe[0], kA1 = sh::kCosineLobe[1], kA2 = sh::kCosineLobe[2];

/// One texture of a layout: its name (also the file's stem) and what each component holds.
struct TextureDesc {
    std::string name;
    std::array<std::string, 4> components;
};

/// The textures a layout writes, in order (`binResolution`: R of a bins:R / moment volume,
/// for the bins layout: 2 R^2 textures in channel order).
std::vector<TextureDesc> layoutTextures(ExportLayout layout, int binResolution = 0);

/// The textures of a basis's own layout (ExportLayout::Basis; Basis::textures).
std::vector<TextureDesc> basisTextures(const Basis& basis);
/// Samples a basis's own layout at every lattice point from the lookup's channel values
/// (VolumeLookup::channelValues): one RGBA float array per texture, x fastest.
std::vector<std::vector<float>> sampleBasis(const IrradianceQuery& query, const TextureLattice& lattice, const Basis& basis);

/// Converts nine SH order-2 radiance coefficients into the layout's texels: 4 floats per
/// texture, textures in layoutTextures order.
void packTexel(ExportLayout layout, const Rgb coeffs[9], float* out);

/// True for the layouts read from SH order-2 coefficients, false for irradiance-vector and bins ones.
bool layoutIsSh(ExportLayout layout);
/// Converts the 54 floats of the 18 irradiance vectors (irradiance_vectors.h order) into the
/// texels of the `vectors` or `compact` layout.
void packVectorTexel(ExportLayout layout, const float v[54], float* out);

/// Samples the query at every lattice point: one RGBA float array per texture, x fastest.
/// Throws FormatError if the layout does not fit the volume kind.
std::vector<std::vector<float>> sampleLayout(const IrradianceQuery& query, const TextureLattice& lattice,
                                             ExportLayout layout, int binResolution = 0);

/// How a texture's four components are stored (texel_format.cpp).
enum class TexelFormat {
    Float16,  ///< IEEE half (the lighting textures with --half)
    Float32,  ///< IEEE float (--float)
    Unorm8,   ///< byte = round(value * 255); reads back as byte / 255 (the depth textures)
};
/// Bytes per component (2, 4, 1) and the manifest's name ("rgba16_sfloat", "rgba32_sfloat",
/// "rgba8_unorm"); the texel is four components.
int componentBytes(TexelFormat format);
const char* texelFormatName(TexelFormat format);
/// The VkFormat (KTX2) and DXGI_FORMAT (DDS) of a texel format.
uint32_t vkFormatOf(TexelFormat format);
uint32_t dxgiFormatOf(TexelFormat format);
/// The lighting textures' format (layout and light visibility): half or float.
TexelFormat lightingTexelFormat(bool half);
/// The depth textures' format: Unorm8 (exact for depth moments, which are k/255), except in
/// an EXR atlas, which has no 8-bit type and keeps the lighting format.
TexelFormat depthTexelFormat(TextureFormat container, bool half);
/// One component as 8-bit unorm: round(clamp(v, 0, 1) * 255); NaN gives 0.
uint8_t unorm8(float v);

/// One texture ready to be written.
struct TextureImage {
    const float* rgba = nullptr;  ///< 4 floats per texel, x fastest, then y, then z
    int dims[3] = {0, 0, 0};
    TexelFormat format = TexelFormat::Float16;
    std::string name;
};

/// Columns and rows of an EXR atlas for `depth` slices: columns = ceil(sqrt(depth)).
struct AtlasGrid {
    int columns = 1, rows = 1;
};
AtlasGrid atlasGrid(int depth);

/// Texel data as little-endian bytes in `format` (`count` components).
std::vector<uint8_t> encodeTexels(const float* values, std::size_t count, TexelFormat format);
/// Writes `bytes` to `path` (throws IoError).
void writeBytes(const std::string& path, const std::vector<uint8_t>& bytes);

/// ValueError naming the texture and texel of the first value outside the half-float range.
void checkHalfRange(const std::vector<std::vector<float>>& textures, const std::vector<TextureDesc>& descs);
/// IoError unless `dir` (or its first existing ancestor) is a writable directory.
void checkOutputDirectory(const std::string& dir);

/// The smallest node spacing of the levels (the texture lattice's default resolution).
double finestSpacing(const std::vector<VolumeLevel>& levels);

/// The file extension of a texture format (".ktx2", ".dds", ".exr", ".raw").
const char* textureExtension(TextureFormat format);

/// The writers return the byte offset of the texel data in the file (0 for EXR, which
/// has its own structure).
uint64_t writeKtx2(const std::string& path, const TextureImage& image);
uint64_t writeDds(const std::string& path, const TextureImage& image);
uint64_t writeExrAtlas(const std::string& path, const TextureImage& image);
uint64_t writeRaw(const std::string& path, const TextureImage& image);

/// Format constants that the manifest reports.
constexpr uint32_t kVkR16G16B16A16Sfloat = 97;
constexpr uint32_t kVkR32G32B32A32Sfloat = 109;
constexpr uint32_t kVkR8G8B8A8Unorm = 37;
constexpr uint32_t kDxgiR16G16B16A16Float = 10;
constexpr uint32_t kDxgiR32G32B32A32Float = 2;
constexpr uint32_t kDxgiR8G8B8A8Unorm = 28;

/// Everything the manifest describes.
struct ManifestInput {
    const ExportOptions* options = nullptr;
    const TextureLattice* lattice = nullptr;
    std::string volumeKind;
    std::string basisKind;   ///< the volume's vdblight:basis (e.g. "bins:4")
    int binResolution = 0;   ///< R of a bins / moment volume (bins layout)
    int momentOrder = 0;     ///< n of a bins / moment volume (1 for bins:R)
    std::string basisFormula;  ///< the layout 'basis': how to evaluate its textures (Basis::formula)
    std::vector<TextureDesc> textures;
    std::vector<std::string> fileNames;  ///< file name of each texture, in order
    std::vector<TexelFormat> texelFormats;  ///< texel format of each texture, in order
    std::vector<uint64_t> dataOffsets;   ///< byte offset of the texels in each file
    /// The volume's direct-light mode and lights (bake --direct); in occlusion mode light i's
    /// visibility is component i % 4 of texture visibilityTextures[i / 4].
    const DirectLightSet* direct = nullptr;
    std::vector<std::string> visibilityTextures;
    /// Shadow edges (shadow_edges.h): their textures' names (edgeTextureDescs), or empty.
    std::vector<std::string> edgeTextures;
    /// Depth moments (depth_moments.h): 0 = the volume has none; 1 = exported as the last
    /// three textures depth_x, depth_y, depth_z; -1 = the volume has them but the lattice is
    /// not its nodes (multi-level volume or --resolution), so they were not exported.
    int depth = 0;
};

/// Occlusion volumes: the textures holding the lights' visibility, four lights per RGBA texture
/// (light_visibility_<first>_<last>), and their texels sampled through the query's lookup.
std::vector<TextureDesc> visibilityTextures(const DirectLightSet& direct);
std::vector<std::vector<float>> sampleVisibility(const IrradianceQuery& query, const TextureLattice& lattice,
                                                 std::size_t lights);
/// Occlusion volumes with shadow edges (shadow_edges.h): per group of four lights the textures
/// light_edge_distance_, light_edge_width_ and light_edge_ramp_<first>_<last> (the last: the
/// ramp of the node's own edge, which a shader subtracts from the visibility texture to get
/// the residual; docs/shadow_visibility.md), in that order. edgeTextures is empty unless the
/// lattice is exactly the nodes of a single-level volume with shadow edges. Without withRamp
/// (the engine-size layouts, whose shaders fetch the corner texels and compute each corner's
/// ramp from its d and w) the ramp textures are left out. withStrips (a volume some of whose
/// nodes have a second edge, hasShadowStrips) adds per light light_edge_strip_<i>: the edge's
/// direction (x, y, z) and the strip's far side (w), last.
std::vector<TextureDesc> edgeTextureDescs(const DirectLightSet& direct, bool withRamp, bool withStrips);
std::vector<std::vector<float>> edgeTextures(const Volume& volume, const TextureLattice& lattice, bool withRamp, bool withStrips);
/// True if some node of the volume has a second edge (shadow_edges.h, kFar > 0).
bool hasShadowStrips(const Volume& volume);
/// Writes one node's texel of every edge texture (edgeTextures's order) at RGBA texel `texel`
/// of `out`: `nodeEdges` the node's shadow_edge::kFloatsPerLight floats per light
/// (VolumeLevel::lightShadowEdges's order). The whole export and the cells (cell_textures.h)
/// share it, so that their texels are the same.
void packEdgeTexel(const float* nodeEdges, std::size_t lights, bool withRamp, bool withStrips, std::size_t texel,
                   std::vector<std::vector<float>>& out);
/// The three depth textures: per texel point (a node) and axis a, RGBA = (mean of the +a
/// face, mean of the -a face, sigma of +a, sigma of -a), in cells. Empty if the lattice is
/// not exactly the nodes of a single-level volume with depth moments.
std::vector<std::vector<float>> depthTextures(const Volume& volume, const TextureLattice& lattice);
/// Their descriptions, in the order depthTextures returns them.
std::vector<TextureDesc> depthTextureDescs();
std::string manifestJson(const ManifestInput& in);

}  // namespace vdblight::exporter
