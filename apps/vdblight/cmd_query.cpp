// vdblight query VOLUME: irradiance E(x, n) at one point or at the rows of a CSV file.
// The answers are the library's (volume_query.h); this file parses options and prints.
#include <iostream>
#include <limits>

#include "app_common.h"
#include "commands.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/query/volume_query.h"

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

void run(const QueryCommand& c) {
    if (c.interp != "trilinear" && c.interp != "tricubic")
        throw ValueError("--interp must be trilinear or tricubic, got '" + c.interp + "'");
    if (c.ivBlend != "bounded" && c.ivBlend != "quadratic" && c.ivBlend != "paper")
        throw ValueError("--iv-blend must be bounded, quadratic or paper, got '" + c.ivBlend + "'");
    if (c.at.empty() == c.points.empty()) throw ValueError("give either --at x,y,z or --points FILE.csv");
    std::vector<Vec3d> world;  // the points in double (volumes far from the origin need it)
    std::vector<Vec3f> normals;
    if (!c.at.empty()) {
        world.push_back(parseTriple(c.at, "--at"));
        normals.push_back(Vec3f(parseTriple(c.normal, "--normal")));
        if (!(length(normals.back()) > 0)) throw ValueError("--normal must not be zero");
    } else {
        for (const ReferencePoint& p : readPointsCsv(c.points, &world)) normals.push_back(p.normal);
    }
    QueryOptions options;
    if (!c.view.empty()) {
        const Vec3f view = Vec3f(parseTriple(c.view, "--view"));
        if (!(length(view) > 0)) throw ValueError("--view must not be zero");
        options.view = normalize(view);
    }
    if (!c.output.empty()) checkOutputWritable(c.output);

    options.outside = c.outside == "error" ? OutsidePolicy::Throw : OutsidePolicy::Clamp;
    options.interpolation = c.interp == "tricubic" ? Interpolation::Tricubic : Interpolation::Trilinear;
    options.ivBlend = iv::parseBlend(c.ivBlend);
    options.depthWeights = !c.noDepthWeights;
    options.raw = c.raw;
    if (c.shOrder != kNotGiven) options.shOrder = c.shOrder;
    options.scenePath = c.scene;
    options.indirectOnly = c.indirectOnly;
    options.shadowRays = c.shadowRays;
    options.streaming = c.stream == "on" ? QueryStreaming::On : c.stream == "off" ? QueryStreaming::Off : QueryStreaming::Auto;
    options.note = [](const std::string& note) { std::cerr << "vdblight: note: " << note << "\n"; };
    const Query query(c.volume, options);

    const QueryCsv answers = queryCsv(query, world, normals);
    emitText(c.output, answers.text);
    if (c.streamReport) {
        if (const StreamedVolume* streamed = query.streamed())
            std::cerr << "vdblight: streamed '" << c.volume << "': read " << streamed->loadedLeaves() << " of "
                      << streamed->totalLeaves() << " leaves (grids in memory: "
                      << formatBytes(double(streamed->residentBytes())) << ")\n";
        else
            std::cerr << "vdblight: read all of '" << c.volume << "'\n";
    }
    const std::size_t count = world.size();
    const std::size_t clamped = answers.clamped, culled = answers.culled, negative = answers.negative;
    if (clamped > 0)
        std::cerr << "vdblight: warning: " << clamped << " of " << count
                  << " points lie outside the volume's node box and were clamped to its boundary\n";
    if (culled > 0)
        std::cerr << "vdblight: warning: " << culled << " of " << count
                  << " points lie in cells inside closed solids whose nodes were culled; their irradiance is reported as 0\n";
    if (negative > 0)
        std::cerr << "vdblight: warning: " << negative << " of " << count
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
