// A volume far from the world origin is read relative to an anchor near its node box, so that
// the float arithmetic of the lookups (locate, weights) works on small numbers (shifted_lookup.h).
#include "shifted_lookup.h"

#include <sstream>

#include "vdblight/core/errors.h"
#include "core/world_frame.h"

namespace vdblight {

namespace {

class ShiftedLookup final : public VolumeLookup {
public:
    ShiftedLookup(std::unique_ptr<VolumeLookup> inner, const Vec3d& anchor) : inner_(std::move(inner)), anchor_(anchor) {}

    Rgb irradiance(const Vec3f& x, const Vec3f& n) const override { return irradianceWorld(Vec3d(x), n); }
    Rgb irradianceWorld(const Vec3d& x, const Vec3f& n) const override {
        try {
            return inner_->irradiance(Vec3f(x - anchor_), n);
        } catch (const ValueError&) {  // OutsidePolicy::Throw: name the world point, not the shifted one
            std::ostringstream s;
            s.precision(12);
            s << "point (" << x.x << ", " << x.y << ", " << x.z << ") is outside the volume";
            throw ValueError(s.str());
        }
    }
    Bounds bounds() const override {
        Bounds b = inner_->bounds();
        b.lo += anchor_;
        b.hi += anchor_;
        return b;
    }
    void shRadiance(const Vec3d& x, Rgb out[9]) const override { inner_->shRadiance(x - anchor_, out); }
    void irradianceVectors(const Vec3d& x, float out[54]) const override { inner_->irradianceVectors(x - anchor_, out); }
    void channelValues(const Vec3d& x, float* out) const override { inner_->channelValues(x - anchor_, out); }
    void setDepthWeights(bool on) override { inner_->setDepthWeights(on); }
    bool depthWeighted() const override { return inner_->depthWeighted(); }

private:
    std::unique_ptr<VolumeLookup> inner_;
    Vec3d anchor_;
};

}  // namespace

std::unique_ptr<VolumeLookup> createAnchored(const Volume& volume, OutsidePolicy outside,
                                             std::unique_ptr<VolumeLookup> (*create)(const Volume&, OutsidePolicy)) {
    const Vec3d anchor = volume.levels.empty() ? Vec3d(0, 0, 0) : recenteringAnchor(volume.levels[0].grid.nodeBounds());
    if (anchor == Vec3d(0, 0, 0)) return create(volume, outside);
    Volume local = volume;
    placeVolumeInWorld(local, -anchor);
    return std::make_unique<ShiftedLookup>(create(local, outside), anchor);
}

std::unique_ptr<VolumeLookup> shiftLookup(std::unique_ptr<VolumeLookup> inner, const Vec3d& anchor) {
    return std::make_unique<ShiftedLookup>(std::move(inner), anchor);
}

}  // namespace vdblight
