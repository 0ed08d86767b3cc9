// Query: a volume opened for `vdblight query`'s questions (volume_query.h).
#include "vdblight/query/volume_query.h"

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "vdblight/basis/basis.h"
#include "vdblight/core/errors.h"
#include "vdblight/query/query.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/light/light.h"
#include "volume/sh_truncate.h"
#include "vdblight/trace/trace.h"
#include "vdblight/volume/vdb_io.h"
#include "core/world_frame.h"

namespace vdblight {

/// A `--direct runtime` volume's direct light, added at query time with shadow rays
/// (scene_lights.h). The scene must be the one baked: its lights must match the volume's list.
struct Query::RuntimeDirect {
    Scene scene;
    std::unique_ptr<Tracer> tracer;
    std::vector<SceneLight> lights;
};

namespace {

std::string megabytes(uint64_t bytes) {
    std::ostringstream s;
    s << bytes / (1 << 20);
    return s.str();
}

}  // namespace

Query::Query(const std::string& path, const QueryOptions& options) : options_(options) {
    // shOrder cuts the volume in memory (sh_truncate.h); streaming reads it as stored.
    const bool cut = options_.shOrder.has_value();
    if (cut && options_.streaming == QueryStreaming::On)
        throw ValueError("--sh-order reads the whole volume: leave out --stream on");
    if (options_.streaming != QueryStreaming::Off && !cut) {
        std::error_code ec;
        const uint64_t bytes = std::filesystem::file_size(path, ec);
        const bool on = options_.streaming == QueryStreaming::On;
        if (on || (!ec && bytes >= kStreamAboveBytes)) {
            streamed_ = std::make_shared<StreamedVolume>(path);
            const std::string why = streamingSupported(*streamed_);
            if (why.empty()) {
                prepare(path);
                return;
            }
            if (on) throw ValueError("--stream on: '" + path + "' cannot be streamed: " + why);
            if (options_.note)
                options_.note("reading all of '" + path + "' (" + megabytes(bytes) +
                              " MiB) into memory: it cannot be streamed: " + why);
            streamed_.reset();
        }
    }
    whole_ = readVolume(path);
    prepare(path);
}

Query::Query(Volume volume, const QueryOptions& options, const std::string& name)
    : options_(options), whole_(std::move(volume)) {
    prepare(name);
}

Query::~Query() = default;

const Volume& Query::volume() const { return streamed_ ? streamed_->header() : whole_; }

void Query::prepare(const std::string& name) {
    if (options_.shOrder) whole_ = truncateSh(std::move(whole_), *options_.shOrder);
    const Volume& v = volume();
    const bool hasDepth = streamed_ ? streamed_->hasDepth() : whole_.hasDepth();
    const OutsidePolicy policy = options_.outside;
    if (!options_.depthWeights && !hasDepth)
        throw ValueError("--no-depth-weights: '" + name + "' has no depth moments (bake --depth-moments)");
    query_ = std::make_unique<IrradianceQuery>(streamed_ ? makeStreamingQuery(streamed_, policy, options_.depthWeights)
                                                         : IrradianceQuery(v, policy, options_.depthWeights));
    const bool moment = query_->viewDependent();
    if (moment && !options_.view)
        throw ValueError("a moment volume ('" + v.basis.kind + "') needs --view vx,vy,vz (towards the eye)");
    if (!moment && options_.view)
        throw ValueError("--view applies to moment volumes (bake --basis moment:N); this one is '" + v.basis.kind + "'");
    if (moment) basis_ = basisOf(v.basis);

    const bool runtime = v.direct.mode == DirectMode::Runtime;
    const std::string& scene = options_.scenePath;
    if (!runtime && (!scene.empty() || options_.indirectOnly))
        throw ValueError(std::string("--scene and --indirect-only apply to volumes baked with --direct runtime; this one is '") +
                         directModeName(v.direct.mode) + "'");
    if (runtime && !options_.indirectOnly) {
        if (scene.empty())
            throw ValueError("'" + name + "' holds indirect light only (bake --direct runtime): give --scene SCENE to add "
                             "its lights' direct light with shadow rays, or --indirect-only for the stored light alone");
        runtime_ = std::make_unique<RuntimeDirect>();
        runtime_->scene = loadScene(scene);
        runtime_->lights = sceneLights(runtime_->scene);
        if (runtime_->lights.size() != v.direct.lights.size())
            throw ValueError("scene '" + scene + "' has " + std::to_string(runtime_->lights.size()) + " lights, the volume lists " +
                             std::to_string(v.direct.lights.size()) + " (baked from another scene?)");
        runtime_->tracer = std::make_unique<Tracer>(runtime_->scene);
    }

    const bool tricubic = options_.interpolation == Interpolation::Tricubic;
    if (tricubic || options_.ivBlend != iv::kDefaultBlend) {
        if (!VectorGridLookup::accepts(v))
            throw ValueError(std::string(tricubic ? "--interp tricubic" : "--iv-blend") +
                             " needs an irradiance-vector volume (bake --method photons); this one is '" + v.basis.kind + "'");
        vectors_ = std::make_unique<VectorGridLookup>(v, policy, options_.interpolation, options_.ivBlend);
    }
    // A volume far from the origin is wrapped in a shifted lookup (shifted_lookup.cpp).
    far_ = recenteringAnchor(query_->bounds()) != Vec3d(0, 0, 0);
}

QueryAnswer Query::at(const Vec3d& x, const Vec3f& normal, uint64_t index) const {
    QueryAnswer a;
    const Vec3f xf(x);
    a.outside = !query_->inside(x);
    // Culled volumes flag points in solid cells. A volume far from the origin is wrapped in a
    // shifted lookup and is not checked (its lookup still returns the documented 0).
    a.culled = query_->inCulledCell(xf);
    const Vec3f n = normalize(normal);
    a.normal = n;
    const Vec3f d = basis_ ? basis_->lookupDirection(n, *options_.view) : n;  // moment: the reflected view vector
    Rgb e = vectors_ ? vectors_->irradiance(xf, d) : query_->irradianceWorld(x, d);
    if (runtime_) {  // the direct light the volume leaves out, with shadow rays
        RayCount rays;
        const Bounds& box = query_->bounds();
        const Vec3d lx = a.outside ? vmin(vmax(x, box.lo), box.hi) : x;
        e += runtimeDirectIrradiance(runtime_->scene, *runtime_->tracer, runtime_->lights, runtime_->scene.toLocal(lx), n,
                                     options_.shadowRays, hashCombine(0x9ee7, index), rays);
    }
    if (!options_.raw && (e.x < 0 || e.y < 0 || e.z < 0)) {  // order-2 SH ringing (docs/methods.md, "Robustness")
        a.negative = true;
        e = Rgb(std::max(e.x, 0.0f), std::max(e.y, 0.0f), std::max(e.z, 0.0f));
    }
    a.irradiance = e;
    return a;
}

}  // namespace vdblight
