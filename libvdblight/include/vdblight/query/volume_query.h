// A baked volume opened for questions: the complete answer of `vdblight query` at a point.
//
// IrradianceQuery (query/query.h) is one kind of volume's lookup. `Query` adds what a caller would
// otherwise have to know about the kind of volume it reads:
// - the choice of lookup: streamed (volume/vdb_io.h) or read whole, cut to fewer SH bands
//   (sh_truncate.h), the irradiance-vector lookup with tricubic interpolation or another
//   blend (query/query.h), depth weights on or off;
// - the lookup direction: a view-dependent basis (moment:N) is evaluated along the view
//   mirrored about the normal (Basis::lookupDirection);
// - the direct light a `--direct runtime` volume leaves out, added with shadow rays through
//   the scene baked (light/light.h);
// - negative irradiance (SH ringing) clamped to 0 unless asked for raw values.
//
//   QueryOptions o;
//   o.view = Vec3f(0, 1, 0);                   // moment volumes only
//   Query q("room.vdb", o);
//   QueryAnswer a = q.at(Vec3d(1, 0.5, 2), Vec3f(0, 1, 0));
//
// Immutable after construction; `at` is thread-safe.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "vdblight/basis/irradiance_vectors.h"
#include "vdblight/core/math.h"
#include "vdblight/query/query.h"
#include "vdblight/volume/volume.h"

namespace vdblight {

class Basis;
class StreamedVolume;

/// Delayed loading of the volume's file (volume/vdb_io.h).
enum class QueryStreaming {
    Auto,  ///< stream files of kStreamAboveBytes and more whose kind streams; read the others whole
    On,    ///< stream, or throw ValueError if the kind cannot be streamed
    Off,   ///< read the whole file
};

/// How a Query answers. The defaults are `vdblight query`'s.
struct QueryOptions {
    OutsidePolicy outside = OutsidePolicy::Clamp;
    /// Irradiance-vector volumes only (anything but the defaults is refused for other kinds).
    Interpolation interpolation = Interpolation::Trilinear;
    iv::Blend ivBlend = iv::kDefaultBlend;
    /// false: plain trilinear even if the volume has depth moments (refused if it has none).
    bool depthWeights = true;
    /// true: keep negative irradiance (SH ringing) instead of clamping each component to 0.
    bool raw = false;
    /// Real-SH volumes: evaluate bands 0..shOrder only (reads the whole volume).
    std::optional<int> shOrder;
    /// Unit vector from the surface towards the eye: required by view-dependent (moment)
    /// volumes, refused by the others.
    std::optional<Vec3f> view;
    /// `--direct runtime` volumes: the scene baked (its lights must match the volume's list);
    /// its lights' direct light is added with `shadowRays` shadow rays per polygon light and point.
    std::string scenePath;
    uint32_t shadowRays = 256;
    /// `--direct runtime` volumes: answer the stored indirect light only (no scene needed).
    bool indirectOnly = false;
    QueryStreaming streaming = QueryStreaming::Auto;
    /// Receives notes that are no errors (a large file read whole because its kind does not
    /// stream). Default: none.
    std::function<void(const std::string&)> note;
};

/// One point's answer.
struct QueryAnswer {
    Rgb irradiance;          ///< W/m^2, RGB: what `vdblight query` prints
    Vec3f normal;            ///< the normal used (the given one normalised)
    bool outside = false;    ///< the point lies outside the node box (clamped, OutsidePolicy::Clamp)
    bool culled = false;     ///< the lookup ends in a culled cell (bake/each_pass.h): the answer is 0
    bool negative = false;   ///< a negative component was clamped to 0 (not with `raw`)
};

class Query {
public:
    /// Opens the file at `path` (streamed or whole, QueryOptions::streaming). Throws
    /// ValueError for options that do not apply to the volume (naming the volume and the
    /// option), FormatError / IoError for unreadable files or scenes.
    explicit Query(const std::string& path, const QueryOptions& options = {});
    /// A volume already in memory; `name` names it in error messages.
    Query(Volume volume, const QueryOptions& options, const std::string& name = "volume");
    ~Query();
    Query(const Query&) = delete;
    Query& operator=(const Query&) = delete;

    /// The answer at world point x for the surface normal n (any length > 0). `index` seeds
    /// the point's shadow rays (runtime direct light): give each point of a list its index
    /// for answers that do not depend on the order or the thread they are computed in.
    QueryAnswer at(const Vec3d& x, const Vec3f& n, uint64_t index = 0) const;
    /// The irradiance alone (QueryAnswer::irradiance).
    Rgb irradiance(const Vec3d& x, const Vec3f& n, uint64_t index = 0) const { return at(x, n, index).irradiance; }

    /// The volume's header (streamed: its metadata and layout, no node values).
    const Volume& volume() const;
    /// The lookup of the stored light (without runtime direct light or clamping).
    const IrradianceQuery& lookup() const { return *query_; }
    /// True if the volume lies far from the origin, where only double positions resolve its
    /// nodes (world_frame.h): print the given double positions, not their float rounding.
    bool farFromOrigin() const { return far_; }
    /// The streamed file, or nullptr if the volume was read whole.
    const StreamedVolume* streamed() const { return streamed_.get(); }

private:
    struct RuntimeDirect;
    /// Everything after reading the file: the checks, the lookups, the scene.
    void prepare(const std::string& name);

    QueryOptions options_;
    Volume whole_;
    std::shared_ptr<StreamedVolume> streamed_;
    std::unique_ptr<IrradianceQuery> query_;
    std::unique_ptr<VolumeLookup> vectors_;  ///< tricubic or another blend (irradiance-vector volumes)
    std::unique_ptr<RuntimeDirect> runtime_;
    std::unique_ptr<Basis> basis_;  ///< the volume's registered basis (for view-dependent kinds)
    bool far_ = false;
};

/// `vdblight query`'s answers at the points `world` with `normals`, as CSV rows
/// x,y,z,nx,ny,nz,E_r,E_g,E_b after a header (positions in float near the origin, as given far
/// from it), and how many answers were clamped to the node box, in culled cells or negative.
struct QueryCsv {
    std::string text;
    std::size_t clamped = 0, culled = 0, negative = 0;
};
QueryCsv queryCsv(const Query& query, const std::vector<Vec3d>& world, const std::vector<Vec3f>& normals);

}  // namespace vdblight
