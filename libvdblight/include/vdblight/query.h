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

#include "vdblight/errors.h"
#include "vdblight/math.h"
#include "vdblight/volume.h"

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
    /// The 18 irradiance vectors (54 floats in the channel order of irradiance_vectors.h)
    /// interpolated trilinearly at x, for irradiance-vector kinds (used by export; at a node
    /// position it returns that node's values). Default: throws FormatError.
    virtual void irradianceVectors(const Vec3d& x, float out[54]) const {
        (void)x;
        (void)out;
        throw FormatError("this volume kind stores no irradiance vectors");
    }
    /// Every channel's stored RGB value (3 floats per channel, in the basis's channel order)
    /// interpolated in space at x with the lookup's own levels rule, for the kinds of the
    /// basis registry (basis.h) read by ChannelLookup (used by export; at a node position it
    /// returns that node's values). Default: throws FormatError.
    virtual void channelValues(const Vec3d& x, float* out) const {
        (void)x;
        (void)out;
        throw FormatError("this volume kind exposes no channel values of a registered basis");
    }
    /// The bins / moment name of channelValues (kept for callers written before basis.h).
    void binValues(const Vec3d& x, float* out) const { channelValues(x, out); }
    /// Visibility-weighted interpolation (depth_moments.h): kinds that support it weight the
    /// corners by the volume's depth moments when it has them, unless switched off here
    /// (for comparison). Default: no depth weighting, nothing to switch.
    virtual void setDepthWeights(bool on) { (void)on; }
    /// True if lookups are weighted by depth moments.
    virtual bool depthWeighted() const { return false; }
    /// Culled volumes (solid_cull.h): true if the cell the lookup at x ends in has a culled
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
    /// moments (depth_moments.h); true (the other constructor): weighted where supported.
    IrradianceQuery(const Volume& volume, OutsidePolicy outside, bool depthWeights);
    /// A query around a lookup built elsewhere (the streamed volumes of query_stream.h).
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
    /// True if the volume's basis stores a view-dependent quantity (moment volumes, bins.h):
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
/// computes each corner's visibility in double from the formula of depth_moments.h written
/// out again here, weights, renormalises and convolves with the generic SH code.
Rgbd referenceDepthWeightedLookup(const Volume& volume, const Vec3d& x, const Vec3d& n);

/// The reference lookups' visibility of a node with depth values d (depth::kFloatsPerNode) from
/// a point at offset o from it, in cells: per axis the face on o's side, Chebyshev's one-sided
/// bound past mean + bias, the product cubed (depth_moments.h, in double).
double referenceNodeVisibility(const float* d, const double o[3]);

}  // namespace vdblight
