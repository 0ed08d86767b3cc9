// The basis module's API: BasisDesc, a basis by name (below), and the Basis interface with
// its registry (second part).
//
// The directional basis a volume stores at each node, by name: its kind and the grid name of
// each channel. Each basis builds its own (BasisDesc::sh2 here, bins::basis, iv::basis,
// iv::compactBasis); volume/volume.h stores one per volume.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "vdblight/core/math.h"

namespace vdblight {

/// The directional basis stored at each node.
struct BasisDesc {
    std::string kind = "sh2";                ///< "sh2": real SH order 2, radiance coefficients
    std::vector<std::string> channelNames;   ///< grid name of each channel, in channel order

    int channelCount() const { return int(channelNames.size()); }
    /// SH order 2 radiance: nine channels named as sh::gridName(j).
    static BasisDesc sh2();

    // Questions about the kind, answered here so that no code outside src/basis/ compares
    // kind strings (issue 30).
    /// "sh2": SH order 2 in its own fixed layout (the lookups and passes written for it).
    bool isSh2() const;
    /// Real SH radiance coefficients: sh2 or sh:N.
    bool isRealSh() const;
    /// The SH order: 2 for sh2, N for sh:N, -1 for bases that are not real SH.
    int shOrder() const;
    /// The irradiance vectors of the photon pass (iv::basis), full or compact (iv::compactBasis).
    bool isIrradianceVectors() const;
    bool isCompactIrradianceVectors() const;
    /// The same kind as `other` (channels not compared): e.g. a probe stage volume
    /// (probeStageBasis) or the full irradiance vectors a compaction needs.
    bool sameKind(const BasisDesc& other) const;
};

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// The Basis interface: what a volume stores at each node and how (pbrt-v4 style: this short
// header is the contract; the concrete bases sit beside it in src/basis/*_basis.cpp and a
// registry creates them from a spec string such as "sh2", "sh:3", "bins:17" or "moment:8").
//
// A basis declares
// - its channels and storage: names (one Vec3f grid each in the .vdb), one RGB float triple
//   per channel, bytes per node;
// - how a sample accumulates into a node: `accumulate` adds radiance arriving from a
//   direction with a Monte-Carlo weight into per-node double accumulators, `finish` turns
//   them into the node's channel values (the generic gather, bake_basis.h, calls only these);
// - how the stored quantity is evaluated: a linear functional of the channels for a
//   direction d (the normal, or for a view-dependent basis the view mirrored about it):
//   E(d) = sum over terms t of weight_t * channel_t (RGB) (the generic lookup, query/query.h);
// - its texture layout for export (which channel and colour goes into which component).
// Adding a basis: one *_basis.cpp file with the class and its BasisKind, one line in
// basis_registry.cpp, its source in libvdblight/CMakeLists.txt, its grids in docs/format.md.

namespace vdblight {

/// One RGBA texture of a basis's export layout: its name and, per component, what it holds
/// (text for the manifest) and where its value comes from (channel * 3 + colour, or -1: 0).
struct BasisTexture {
    std::string name;
    std::array<std::string, 4> components;
    std::array<int, 4> source{{-1, -1, -1, -1}};
};

class Basis {
public:
    virtual ~Basis() = default;

    // --- Channels and storage -----------------------------------------------------------
    /// Kind (written as vdblight:basis, e.g. "sh:3") and channel names (grid names).
    virtual const BasisDesc& desc() const = 0;
    int channelCount() const { return desc().channelCount(); }
    /// Every channel is one RGB triple of floats: a Vec3f grid in the file.
    static constexpr int kValuesPerChannel = 3;
    std::size_t floatsPerNode() const { return std::size_t(channelCount()) * kValuesPerChannel; }
    std::size_t bytesPerNode() const { return floatsPerNode() * sizeof(float); }
    /// What the channels hold, one short phrase for `vdblight info` ("radiance SH coefficients, bands 0..3").
    virtual std::string describe() const = 0;

    // --- Baking ---------------------------------------------------------------------------
    /// Accumulator entries (RGB doubles) per node while baking.
    virtual std::size_t accumulatorSize() const = 0;
    /// Adds a sample: radiance L arriving from unit direction w with Monte-Carlo weight
    /// `weight` (1 / (pdf * samples), so that the sum over samples estimates integrals over
    /// the sphere). `acc` has accumulatorSize() entries, zero at the start of a node.
    virtual void accumulate(const Vec3f& w, const Rgbd& radiance, double weight, Rgbd* acc) const = 0;
    /// The node's channel values (floatsPerNode() floats, channel-major RGB) from its accumulator.
    virtual void finish(const Rgbd* acc, float* values) const = 0;

    // --- Evaluation -----------------------------------------------------------------------
    /// True if the stored quantity depends on the view (moment:n): look it up along the view
    /// mirrored about the normal.
    virtual bool viewDependent() const { return false; }
    /// The direction a lookup evaluates for unit normal n and unit view v (towards the eye).
    Vec3f lookupDirection(const Vec3f& n, const Vec3f& v) const;
    /// Most terms `terms` returns.
    virtual int maxTerms() const = 0;
    /// The stored quantity in direction d as a linear functional of the node's channels:
    /// writes up to maxTerms() (channel, weight) pairs and returns their count.
    virtual int terms(const Vec3f& d, int* channels, float* weights) const = 0;
    /// E(d) of one node's channel values (3 floats per channel), from `terms`.
    Rgb evaluate(const float* values, const Vec3f& d) const;
    /// How many leading channels are real SH radiance coefficients in sh.h's convention
    /// (index l (l + 1) + m, bands 0..l): 9 for sh2, (N + 1)^2 for sh:N, 0 for bases that are
    /// not SH. Truncating orthonormal SH is projecting onto fewer bands, so an sh:4 volume's
    /// first nine channels are its SH order 2 (what the engines' L2 layouts export).
    virtual int shCoefficients() const { return 0; }

    // --- Export ---------------------------------------------------------------------------
    /// The textures of the basis's own export layout (`export --layout basis`). Default: one
    /// texture per channel named after it, RGB = the channel, alpha 0.
    virtual std::vector<BasisTexture> textures() const;
    /// How a renderer evaluates the exported textures (one line for the manifest).
    virtual std::string formula() const = 0;
};

/// A registered kind of basis.
struct BasisKind {
    const char* syntax;  ///< e.g. "sh:N", for --help and error messages
    const char* help;    ///< one phrase for --help
    /// The basis of `text`, nullptr if `text` is not of this kind; ValueError (one line naming
    /// `text`) if it is of this kind but malformed.
    std::unique_ptr<Basis> (*parse)(const std::string& text);
    /// The basis a volume's BasisDesc (kind and channel names) stores, nullptr if not this kind.
    std::unique_ptr<Basis> (*fromDesc)(const BasisDesc& desc);
};

/// Every registered basis kind (basis_registry.cpp), in the order they are tried.
const std::vector<BasisKind>& basisKinds();
/// Creates the basis of a spec string. Throws ValueError listing the syntaxes if no kind takes it.
std::unique_ptr<Basis> makeBasis(const std::string& text);
/// The registered basis a volume stores, or nullptr (irradiance vectors, probe stages, unknown kinds).
std::unique_ptr<Basis> basisOf(const BasisDesc& desc);
/// "sh2, sh:N (...), bins:R (...), ...": the registered syntaxes and their help, for --help.
std::string basisChoices();

}  // namespace vdblight
