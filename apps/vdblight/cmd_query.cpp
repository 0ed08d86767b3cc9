// vdblight query VOLUME: irradiance E(x, n) at one point or at the rows of a CSV file.
#include <algorithm>
#include <sstream>
#include <iostream>

#include "app_common.h"
#include "commands.h"
#include "vdblight/bins.h"
#include "vdblight/errors.h"
#include "vdblight/query.h"
#include "vdblight/sh_truncate.h"
#include "vdblight/scene.h"
#include "vdblight/scene_lights.h"
#include "vdblight/scene_origin.h"
#include "vdblight/trace.h"
#include "vdblight/vdb_io.h"
#include "vdblight/vector_grid_lookup.h"
#include "vdblight/query_stream.h"
#include "vdblight/vdb_stream.h"

#include <filesystem>
#include <limits>

namespace vdblight::app {

namespace {
constexpr int kNotGiven = std::numeric_limits<int>::min();

struct QueryCommand {
    std::string volume;
    std::string at, normal = "0,1,0";
    std::string points;
    std::string output;
    std::string outside = "clamp";
    std::string interp = "trilinear";
    std::string ivBlend = iv::blendName(iv::kDefaultBlend);  // irradiance-vector volumes: E(n) from the six vectors
    std::string view;  // moment volumes: view vector, mirrored about the normal (bins.h)
    bool raw = false;  // keep negative irradiance (SH ringing) instead of clamping it to 0
    std::string scene;        // --direct runtime volumes: the scene whose lights are added with shadows
    bool indirectOnly = false;  // --direct runtime volumes: the stored indirect light only
    uint32_t shadowRays = 256;  // per polygon light and point, with --scene
    bool noDepthWeights = false;  // plain trilinear even if the volume has depth moments
    std::string stream = "auto";  // delayed loading: auto (files >= kStreamAboveBytes), on, off
    bool streamReport = false;    // print how many leaves streaming read
    int shOrder = kNotGiven;      // bands 0..shOrder of a real-SH volume (what an engine's L2 probe holds)
};

/// The volume as a query reads it: streamed (only the leaves looked up are read; vdb_stream.h)
/// or read whole. `header` is the Volume (whole) or its header (streamed: no node values).
struct OpenedVolume {
    Volume whole;
    std::shared_ptr<StreamedVolume> streamed;
    const Volume& header() const { return streamed ? streamed->header() : whole; }
    bool hasDepth() const { return streamed ? streamed->hasDepth() : whole.hasDepth(); }
};

OpenedVolume openForQuery(const QueryCommand& c) {
    OpenedVolume v;
    // --sh-order cuts the volume in memory (sh_truncate.h); streaming reads it as stored.
    if (c.shOrder != kNotGiven && c.stream == "on") throw ValueError("--sh-order reads the whole volume: leave out --stream on");
    if (c.stream != "off" && c.shOrder == kNotGiven) {
        std::error_code ec;
        const uint64_t bytes = std::filesystem::file_size(c.volume, ec);
        if (c.stream == "on" || (!ec && bytes >= kStreamAboveBytes)) {
            v.streamed = std::make_shared<StreamedVolume>(c.volume);
            const std::string why = streamingSupported(*v.streamed);
            if (why.empty()) return v;
            if (c.stream == "on") throw ValueError("--stream on: '" + c.volume + "' cannot be streamed: " + why);
            std::cerr << "vdblight: note: reading all of '" << c.volume << "' (" << bytes / (1 << 20)
                      << " MiB) into memory: it cannot be streamed: " << why << "\n";
            v.streamed.reset();
        }
    }
    v.whole = readVolume(c.volume);
    return v;
}

/// A `--direct runtime` volume's direct light, added at query time with shadow rays
/// (scene_lights.h). The scene must be the one baked: its lights must match the volume's list.
struct RuntimeDirect {
    Scene scene;
    std::unique_ptr<Tracer> tracer;
    std::vector<SceneLight> lights;
};

std::unique_ptr<RuntimeDirect> runtimeDirect(const QueryCommand& c, const Volume& volume) {
    const bool runtime = volume.direct.mode == DirectMode::Runtime;
    if (!runtime && (!c.scene.empty() || c.indirectOnly))
        throw ValueError(std::string("--scene and --indirect-only apply to volumes baked with --direct runtime; this one is '") +
                         directModeName(volume.direct.mode) + "'");
    if (!runtime || c.indirectOnly) return nullptr;
    if (c.scene.empty())
        throw ValueError("'" + c.volume + "' holds indirect light only (bake --direct runtime): give --scene SCENE to add "
                         "its lights' direct light with shadow rays, or --indirect-only for the stored light alone");
    auto r = std::make_unique<RuntimeDirect>();
    r->scene = loadScene(c.scene);
    r->lights = sceneLights(r->scene);
    if (r->lights.size() != volume.direct.lights.size())
        throw ValueError("scene '" + c.scene + "' has " + std::to_string(r->lights.size()) + " lights, the volume lists " +
                         std::to_string(volume.direct.lights.size()) + " (baked from another scene?)");
    r->tracer = std::make_unique<Tracer>(r->scene);
    return r;
}

void run(const QueryCommand& c) {
    if (c.interp != "trilinear" && c.interp != "tricubic")
        throw ValueError("--interp must be trilinear or tricubic, got '" + c.interp + "'");
    if (c.ivBlend != "bounded" && c.ivBlend != "quadratic" && c.ivBlend != "paper")
        throw ValueError("--iv-blend must be bounded, quadratic or paper, got '" + c.ivBlend + "'");
    if (c.at.empty() == c.points.empty()) throw ValueError("give either --at x,y,z or --points FILE.csv");
    std::vector<ReferencePoint> points;
    std::vector<Vec3d> world;  // the points in double (volumes far from the origin need it)
    if (!c.at.empty()) {
        ReferencePoint p;
        world.push_back(parseTriple(c.at, "--at"));
        p.position = Vec3f(world.back());
        p.normal = Vec3f(parseTriple(c.normal, "--normal"));
        if (!(length(p.normal) > 0)) throw ValueError("--normal must not be zero");
        points.push_back(p);
    } else {
        points = readPointsCsv(c.points, &world);
    }
    Vec3f view;
    if (!c.view.empty()) {
        view = Vec3f(parseTriple(c.view, "--view"));
        if (!(length(view) > 0)) throw ValueError("--view must not be zero");
        view = normalize(view);
    }
    if (!c.output.empty()) checkOutputWritable(c.output);

    OpenedVolume opened = openForQuery(c);
    if (c.shOrder != kNotGiven) opened.whole = truncateSh(std::move(opened.whole), c.shOrder);
    const Volume& volume = opened.header();
    const OutsidePolicy policy = c.outside == "error" ? OutsidePolicy::Throw : OutsidePolicy::Clamp;
    if (c.noDepthWeights && !opened.hasDepth())
        throw ValueError("--no-depth-weights: '" + c.volume + "' has no depth moments (bake --depth-moments)");
    const IrradianceQuery query = opened.streamed ? makeStreamingQuery(opened.streamed, policy, !c.noDepthWeights)
                                                  : IrradianceQuery(volume, policy, !c.noDepthWeights);
    const bool moment = query.viewDependent();
    if (moment && c.view.empty())
        throw ValueError("a moment volume ('" + volume.basis.kind + "') needs --view vx,vy,vz (towards the eye)");
    if (!moment && !c.view.empty())
        throw ValueError("--view applies to moment volumes (bake --basis moment:N); this one is '" + volume.basis.kind + "'");
    const std::unique_ptr<RuntimeDirect> runtime = runtimeDirect(c, volume);
    std::unique_ptr<VolumeLookup> cubic;  // --interp tricubic or another --iv-blend (irradiance-vector volumes)
    const iv::Blend blend = iv::parseBlend(c.ivBlend);
    if (c.interp == "tricubic" || blend != iv::kDefaultBlend) {
        if (!VectorGridLookup::accepts(volume))
            throw ValueError(std::string(c.interp == "tricubic" ? "--interp tricubic" : "--iv-blend") +
                             " needs an irradiance-vector volume (bake --method photons); this one is '" +
                             volume.basis.kind + "'");
        cubic = std::make_unique<VectorGridLookup>(
            volume, policy, c.interp == "tricubic" ? Interpolation::Tricubic : Interpolation::Trilinear, blend);
    }

    std::ostringstream out;
    out.precision(9);
    out << "x,y,z,nx,ny,nz,E_r,E_g,E_b\n";
    std::size_t clamped = 0, culled = 0, negative = 0;
    // Culled volumes flag points in solid cells. A volume far from the origin is wrapped in a
    // shifted lookup and is not checked here (its lookup still returns the documented 0).
    const bool far = recenteringAnchor(query.bounds()) != Vec3d(0, 0, 0);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const ReferencePoint& p = points[i];
        if (!query.inside(world[i])) ++clamped;
        if (query.inCulledCell(p.position)) ++culled;
        const Vec3f n = normalize(p.normal);
        const Vec3f d = moment ? normalize(bins::reflectView(view, n)) : n;  // moment: the reflected view vector
        Rgb e = cubic ? cubic->irradiance(p.position, d) : query.irradianceWorld(world[i], d);
        if (runtime) {  // the direct light the volume leaves out, with shadow rays
            RayCount rays;
            const Vec3d lx = query.inside(world[i]) ? world[i] : vmin(vmax(world[i], query.bounds().lo), query.bounds().hi);
            e += runtimeDirectIrradiance(runtime->scene, *runtime->tracer, runtime->lights, runtime->scene.toLocal(lx), n,
                                         c.shadowRays, hashCombine(0x9ee7, i), rays);
        }
        if (!c.raw && (e.x < 0 || e.y < 0 || e.z < 0)) {  // order-2 SH ringing (docs/methods.md)
            ++negative;
            e = Rgb(std::max(e.x, 0.0f), std::max(e.y, 0.0f), std::max(e.z, 0.0f));
        }
        const Vec3d x = far ? world[i] : Vec3d(p.position);  // near the origin: printed as before
        out << x.x << ',' << x.y << ',' << x.z << ',' << n.x << ',' << n.y << ',' << n.z
            << ',' << e.x << ',' << e.y << ',' << e.z << '\n';
    }
    emitText(c.output, out.str());
    if (c.streamReport) {
        if (opened.streamed)
            std::cerr << "vdblight: streamed '" << c.volume << "': read " << opened.streamed->loadedLeaves() << " of "
                      << opened.streamed->totalLeaves() << " leaves (grids in memory: "
                      << formatBytes(double(opened.streamed->residentBytes())) << ")\n";
        else
            std::cerr << "vdblight: read all of '" << c.volume << "'\n";
    }
    if (clamped > 0)
        std::cerr << "vdblight: warning: " << clamped << " of " << points.size()
                  << " points lie outside the volume's node box and were clamped to its boundary\n";
    if (culled > 0)
        std::cerr << "vdblight: warning: " << culled << " of " << points.size()
                  << " points lie in cells inside closed solids whose nodes were culled; their irradiance is reported as 0\n";
    if (negative > 0)
        std::cerr << "vdblight: warning: " << negative << " of " << points.size()
                  << " points had negative irradiance (SH ringing), clamped to 0; --raw gives the raw value\n";
}
}  // namespace

void addQueryCommand(CLI::App& app) {
    auto c = std::make_shared<QueryCommand>();
    CLI::App* cmd = app.add_subcommand("query", "Irradiance E(x, n) from a baked volume (CSV on stdout)");
    cmd->add_option("volume", c->volume, "Volume (.vdb) written by vdblight bake")->required();
    cmd->add_option("--at", c->at, "Point x,y,z");
    cmd->add_option("--normal", c->normal, "Surface normal nx,ny,nz for --at")->capture_default_str();
    cmd->add_option("--points", c->points, "CSV of x,y,z,nx,ny,nz rows");
    cmd->add_option("-o,--output", c->output, "Write the CSV here instead of stdout");
    cmd->add_option("--outside", c->outside, "Points outside the node box: clamp (to the nearest boundary point) or error")
        ->check(CLI::IsMember({"clamp", "error"}))
        ->capture_default_str();
    cmd->add_option("--interp", c->interp, "Spatial interpolation: trilinear or tricubic (irradiance-vector volumes)")
        ->capture_default_str();
    cmd->add_option("--iv-blend", c->ivBlend,
                    "Irradiance-vector volumes: E(n) from the six vectors: bounded (quadratic clamped to the "
                    "bounds the vectors prove), quadratic (exact for SH bands 0-2, uniform light included) or "
                    "paper (Pacanowski et al. 4.1 n^2 blend, a lower bound: 3/4 of uniform light on average)")
        ->capture_default_str();
    cmd->add_option("--view", c->view,
                    "Moment volumes (bake --basis moment:N): unit vector from the surface towards the eye; the "
                    "lookup direction is its mirror about the normal (Greger et al. section 5.2)");
    cmd->add_flag("--no-depth-weights", c->noDepthWeights,
                  "Plain trilinear interpolation for a volume with depth moments (for comparison)");
    cmd->add_flag("--raw", c->raw,
                  "Print the raw reconstructed irradiance, negative where order-2 SH rings (default: negative "
                  "components clamped to 0)");
    cmd->add_option("--stream", c->stream,
                    "Delayed loading, reading only the leaves (8^3 nodes) the points touch, for volumes larger than "
                    "memory: auto (files of 256 MiB and more whose kind streams: real SH, sh2 or sh:N as the default bake "
                    "stores, uniform or levels, with depth moments and --direct occlusion; others are read whole), on (refuse other kinds), off (read the whole file). "
                    "The answers are the same bits either way")
        ->check(CLI::IsMember({"auto", "on", "off"}))
        ->capture_default_str();
    cmd->add_flag("--stream-report", c->streamReport,
                  "Print (stderr) how many leaves of the file were read (streamed) or that all of it was");
    cmd->add_option("--scene", c->scene,
                    "--direct runtime volumes: the scene baked; its lights' direct light is added with shadow rays");
    cmd->add_option("--sh-order", c->shOrder,
                    "Real-SH volumes: evaluate bands 0..N only (e.g. 2 for a volume baked with SH order 4, the "
                    "default: what export's sh2 / sh2-packed layouts and an engine's L2 probes hold)");
    cmd->add_flag("--indirect-only", c->indirectOnly, "--direct runtime volumes: print the stored indirect light only");
    cmd->add_option("--shadow-rays", c->shadowRays, "With --scene: shadow rays per polygon light and point")
        ->capture_default_str()
        ->check(CLI::Range(1u, 1u << 20));
    cmd->callback([c] { run(*c); });
}

}  // namespace vdblight::app
