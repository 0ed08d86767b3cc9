// The query module's API, in three parts: IrradianceQuery and the lookups behind it (below),
// the streamed query of a file larger than memory, and the irradiance-vector grid lookup.
//
// Run-time lookup of irradiance E(x, n) from any kind of volume.
//
// `IrradianceQuery` is what applications use: built once from a Volume, immutable,
// thread-safe, no allocation per lookup. Behind it sits one `VolumeLookup` per kind of
// volume (basis x layout), chosen from a small registry (query/registry.cpp). A new kind
// plugs in by adding its lookup file and one registration line.
//
// The SH order-2 uniform lookup (Kontkanen & Laine eq. 3; Greger et al. section 3.3):
// trilinear interpolation of the nodes' radiance coefficients, then the cosine-lobe
// convolution for the normal, with the constants A_l folded into the coefficients.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "vdblight/core/errors.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "vdblight/core/math.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/volume/volume.h"

namespace vdblight {

/// What a lookup does with a point outside the volume's node box.
enum class OutsidePolicy {
    Clamp,  ///< use the nearest point of the node box (documented default; NaN -> the origin corner)
    Throw,  ///< throw ValueError naming the point
};

/// One kind of volume's lookup. Implementations copy what they need from the Volume into
/// a layout that is fast to read.
class VolumeLookup {
public:
    virtual ~VolumeLookup() = default;
    /// Irradiance (W/m^2, RGB) at x for the unit normal n.
    virtual Rgb irradiance(const Vec3f& x, const Vec3f& n) const = 0;
    /// The same at a double-precision world point (a volume far from the origin resolves
    /// its nodes only in double). Default: rounds x to float.
    virtual Rgb irradianceWorld(const Vec3d& x, const Vec3f& n) const { return irradiance(Vec3f(x), n); }
    /// The box in which lookups interpolate (outside it the outside policy applies).
    virtual Bounds bounds() const = 0;
    /// The nine RGB radiance coefficients of SH order 2 (docs/format.md convention, not
    /// convolved) reconstructed at x, for kinds whose basis is SH order 2 (used by export,
    /// hence double positions: at a node position it returns that node's values).
    /// Default: throws FormatError, because the kind stores another basis.
    virtual void shRadiance(const Vec3d& x, Rgb out[9]) const {
        (void)x;
        (void)out;
        throw FormatError("this volume kind stores no SH order-2 coefficients");
    }
    /// The 18 irradiance vectors (54 floats in the channel order of basis/irradiance_vectors.h)
    /// interpolated trilinearly at x, for irradiance-vector kinds (used by export; at a node
    /// position it returns that node's values). Default: throws FormatError.
    virtual void irradianceVectors(const Vec3d& x, float out[54]) const {
        (void)x;
        (void)out;
        throw FormatError("this volume kind stores no irradiance vectors");
    }
    /// Every channel's stored RGB value (3 floats per channel, in the basis's channel order)
    /// interpolated in space at x with the lookup's own levels rule, for the kinds of the
    /// basis registry (basis/basis.h) read by ChannelLookup (used by export; at a node position it
    /// returns that node's values). Default: throws FormatError.
    virtual void channelValues(const Vec3d& x, float* out) const {
        (void)x;
        (void)out;
        throw FormatError("this volume kind exposes no channel values of a registered basis");
    }
    /// The bins / moment name of channelValues (kept for callers written before basis/basis.h).
    void binValues(const Vec3d& x, float* out) const { channelValues(x, out); }
    /// Visibility-weighted interpolation (basis/depth_moments.h): kinds that support it weight the
    /// corners by the volume's depth moments when it has them, unless switched off here
    /// (for comparison). Default: no depth weighting, nothing to switch.
    virtual void setDepthWeights(bool on) { (void)on; }
    /// True if lookups are weighted by depth moments.
    virtual bool depthWeighted() const { return false; }
    /// Culled volumes (bake/each_pass.h): true if the cell the lookup at x ends in has a culled
    /// corner (inside closed geometry; the lookup returns 0 there). Default: false, for kinds
    /// that hold no culled volumes, and for wrappers (a volume far from the origin, direct
    /// light), which do not report it.
    virtual bool inCulledCell(const Vec3f& x) const {
        (void)x;
        return false;
    }
};

/// A registry entry: `accepts` says whether a volume is of this kind, `create` builds it.
struct LookupKind {
    const char* name;
    bool (*accepts)(const Volume&);
    std::unique_ptr<VolumeLookup> (*create)(const Volume&, OutsidePolicy);
};
/// Every known kind, in the order they are tried.
const std::vector<LookupKind>& lookupKinds();

class IrradianceQuery {
public:
    /// Throws FormatError if no registered lookup accepts the volume (naming its basis).
    explicit IrradianceQuery(const Volume& volume, OutsidePolicy outside = OutsidePolicy::Clamp);
    /// `depthWeights` false: plain trilinear interpolation even if the volume carries depth
    /// moments (basis/depth_moments.h); true (the other constructor): weighted where supported.
    IrradianceQuery(const Volume& volume, OutsidePolicy outside, bool depthWeights);
    /// A query around a lookup built elsewhere (the streamed volumes of query/query.h).
    IrradianceQuery(std::unique_ptr<VolumeLookup> lookup, const char* kind);

    /// Irradiance (W/m^2, RGB) at x for the unit normal n.
    Rgb irradiance(const Vec3f& x, const Vec3f& n) const { return lookup_->irradiance(x, n); }
    /// The same at a world point in double: use this for volumes far from the origin (the
    /// volume is then read relative to an anchor near its box, shifted_lookup.cpp).
    Rgb irradianceWorld(const Vec3d& x, const Vec3f& n) const { return lookup_->irradianceWorld(x, n); }
    /// True if x lies inside the volume's node box.
    bool inside(const Vec3f& x) const { return bounds_.contains(Vec3d(x)); }
    bool inside(const Vec3d& x) const { return bounds_.contains(x); }
    const Bounds& bounds() const { return bounds_; }
    /// Name of the lookup kind in use (e.g. "sh2-uniform").
    const char* kind() const { return kind_; }
    /// True if lookups weight the corners by the volume's depth moments.
    bool depthWeighted() const { return lookup_->depthWeighted(); }
    /// True if the volume's basis stores a view-dependent quantity (moment volumes, basis/bins.h):
    /// look it up along Basis::lookupDirection(n, view) (the view mirrored about n) instead of n.
    bool viewDependent() const { return viewDependent_; }
    /// True if the lookup at x ends in a culled cell (VolumeLookup::inCulledCell).
    bool inCulledCell(const Vec3f& x) const { return lookup_->inCulledCell(x); }
    /// The lookup behind this query (for per-basis hooks such as shRadiance).
    const VolumeLookup& lookup() const { return *lookup_; }

private:
    std::unique_ptr<VolumeLookup> lookup_;
    Bounds bounds_;
    const char* kind_ = "";
    bool viewDependent_ = false;
};

/// The simple, obviously correct lookup used to test the fast SH lookups: reads the volume's
/// own arrays, interpolates in double and convolves with the generic SH code.
Rgbd referenceLookup(const Volume& volume, const Vec3d& x, const Vec3d& n);

/// The simple lookup the depth-weighted SH lookups (uniform and levels) are tested against:
/// finds the finest cell at x through the volume's own lists (like referenceLevelsLookup),
/// computes each corner's visibility in double from the formula of basis/depth_moments.h written
/// out again here, weights, renormalises and convolves with the generic SH code.
Rgbd referenceDepthWeightedLookup(const Volume& volume, const Vec3d& x, const Vec3d& n);

/// The reference lookups' visibility of a node with depth values d (depth::kFloatsPerNode) from
/// a point at offset o from it, in cells: per axis the face on o's side, Chebyshev's one-sided
/// bound past mean + bias, the product cubed (basis/depth_moments.h, in double).
double referenceNodeVisibility(const float* d, const double o[3]);

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// Lookups on a volume read through delayed loading (volume/vdb_io.h): the same answers, bit for
// bit, as IrradianceQuery on readVolume's Volume, but only the leaves around the points looked
// up are read from the file, so a world larger than memory can be queried.
//
//   auto file = std::make_shared<StreamedVolume>("world.vdb");
//   if (streamingSupported(*file).empty()) {
//       IrradianceQuery q = makeStreamingQuery(file, OutsidePolicy::Clamp, true);
//       Rgb e = q.irradianceWorld({12.0, 1.5, -40.0}, {0, 1, 0});
//   }
//
// Kinds: every kind the default bake and the presets write. SH order 2 (`sh2`: uniform, or
// bilevel / adaptive levels culled or not) and real SH of any order (`sh:N`, the default bake's
// `sh:4`: uniform or levels), with or without depth moments, near or far from the origin,
// --direct baked, runtime and occlusion (the default: per-light visibility). The arithmetic is
// the in-memory lookup's (ShUniformLookup, ShLevelsLookup, ChannelLookup / ShFourUniformLookup,
// OcclusionLookup). Other kinds (bins, moments, irradiance vectors, culled sh:N) are refused
// with the reason; `vdblight query` then reads the whole file unless told --stream on.

namespace vdblight {

/// Empty if makeStreamingQuery supports the file's kind, else the reason (one sentence).
std::string streamingSupported(const StreamedVolume& volume);

/// The lookup for `volume`, kind name "sh2-uniform-streamed", "sh2-levels-streamed",
/// "sh4-uniform-streamed" (sh:4 on one level) or "basis-streamed" (other sh:N); with
/// per-light visibility its lookup is also a LightVisibility (light_visibility.h), as
/// OcclusionLookup is. A missing node of a refined cell (a corrupt file, which readVolume
/// refuses) reads as 0 instead of being refused. `depthWeights` as in IrradianceQuery(volume,
/// outside, depthWeights). Throws FormatError for unsupported kinds.
IrradianceQuery makeStreamingQuery(std::shared_ptr<const StreamedVolume> volume, OutsidePolicy outside,
                                   bool depthWeights = true);

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// Lookup of irradiance-vector volumes (basis "irradiance_vectors", one level): spatial
// interpolation of the six vectors, then E(n) by the blend (basis/irradiance_vectors.h): Bounded by
// default (the quadratic blend, exact for SH bands 0-2 and uniform light, clamped to the
// bounds the vectors prove), Quadratic, or Paper (Pacanowski et al. section 4.1: the three
// vectors of n's signs blended by n^2, a lower bound of E; only those three are interpolated).
//
// Spatial interpolation is trilinear, or tricubic: per axis the Catmull-Rom cubic through
// four nodes (one-sided at the box's faces by linear extrapolation of the end nodes), which
// reproduces linear fields exactly and is C1 across cells.
//
// Depth moments (basis/depth_moments.h, `bake --method photons --depth-moments`): where the volume
// has them, the trilinear weights are multiplied by each corner's visibility from the point,
// as in the SH lookups (query/depth_weights.h), so that a point behind a thin wall does not
// read the nodes on the other side. Tricubic interpolation ignores them (its sixty-four taps
// have no visibility test): depthWeighted() says which applies.
//
// It also reads the compact colour + direction form (basis "irradiance_vectors_compact",
// irradiance_vectors_compact.h): colour and direction are interpolated the same way, then
// decoded by iv::compactIrradiance.

namespace vdblight {

enum class Interpolation { Trilinear, Tricubic };

class VectorGridLookup final : public VolumeLookup {
public:
    VectorGridLookup(const Volume& volume, OutsidePolicy outside, Interpolation interp = Interpolation::Trilinear,
                     iv::Blend blend = iv::kDefaultBlend);
    Rgb irradiance(const Vec3f& x, const Vec3f& n) const override;
    Bounds bounds() const override { return grid_.nodeBounds(); }
    void setDepthWeights(bool on) override { depthWeights_ = on && !depth_.empty() && interp_ == Interpolation::Trilinear; }
    bool depthWeighted() const override { return depthWeights_; }
    /// Trilinear in double (whatever the Interpolation), snapped onto nodes within 1e-9 cells,
    /// depth-weighted as irradiance() is.
    void irradianceVectors(const Vec3d& x, float out[54]) const override;

    static bool accepts(const Volume& volume);

private:
    void locate(const Vec3f& x, int idx[3], float frac[3]) const;
    int weightsAndNodes(int axis, int i, float f, int nodes[4], float w[4]) const;

    GridSpec grid_;
    OutsidePolicy outside_;
    Interpolation interp_;
    iv::Blend blend_;
    Vec3f origin_;
    float invSpacing_;
    bool compact_ = false;
    int stride_ = 0;           ///< floats per node
    int perDirection_ = 0;     ///< floats per direction delta (9 full, 6 compact)
    std::vector<float> data_;  ///< the volume's level 0, stride_ floats per node
    std::vector<float> depth_;  ///< depth::kFloatsPerNode per node, or empty
    bool depthWeights_ = false;
};

/// The simple lookup used to test VectorGridLookup: trilinear in double over the volume's
/// own arrays (full form), then iv::referenceIrradiance. With depthWeights and a volume with
/// depth moments, the corners are weighted by referenceNodeVisibility (query/query.h).
Rgbd referenceVectorLookup(const Volume& volume, const Vec3d& x, const Vec3d& n, iv::Blend blend = iv::kDefaultBlend,
                           bool depthWeights = true);

}  // namespace vdblight
