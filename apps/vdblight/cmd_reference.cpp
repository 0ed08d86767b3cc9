// vdblight reference [SCENE] --points FILE.csv: ground-truth irradiance without SH or grid.
#include <iostream>

#include "app_common.h"
#include "commands.h"
#include "vdblight/core/errors.h"
#include "vdblight/trace/trace.h"

namespace vdblight::app {

namespace {
struct ReferenceCommand {
    SceneOptions scene;
    std::string points;
    std::string output;
    uint32_t samples = 65536;
    uint64_t seed = 1;
    int threads = 0;
    bool quiet = false;
};

void run(const ReferenceCommand& c) {
    std::vector<Vec3d> world;
    std::vector<ReferencePoint> points = readPointsCsv(c.points, &world);
    if (!c.output.empty()) checkOutputWritable(c.output);
    const Scene scene = loadSceneFromOptions(c.scene, c.quiet);
    for (std::size_t i = 0; i < points.size(); ++i) points[i].position = scene.toLocal(world[i]);  // world -> local frame
    const Tracer tracer(scene);
    ReferenceOptions options;
    options.samples = c.samples;
    options.seed = c.seed;
    options.threads = c.threads;
    options.transport = transportFromOptions(c.scene);
    ProgressBar progress(c.quiet);
    const std::vector<ReferenceResult> results = referenceIrradiance(scene, tracer, points, options, &progress);

    emitText(c.output, referenceCsv(scene, points, results));
}
}  // namespace

void addReferenceCommand(CLI::App& app) {
    auto c = std::make_shared<ReferenceCommand>();
    CLI::App* cmd = app.add_subcommand(
        "reference", "Ground-truth irradiance at points (direct hemisphere integration, no SH, no grid)");
    addSceneOptions(*cmd, c->scene);
    cmd->add_option("--points", c->points, "CSV of x,y,z,nx,ny,nz rows")->required();
    cmd->add_option("-o,--output", c->output, "Write the CSV here instead of stdout");
    cmd->add_option("--samples", c->samples, "Hemisphere samples per point")->capture_default_str()->check(CLI::Range(1u, 1u << 31));
    cmd->add_option("--seed", c->seed, "Random seed")->capture_default_str();
    cmd->add_option("--threads", c->threads, "Worker threads (0 = all cores)")->capture_default_str();
    cmd->add_flag("-q,--quiet", c->quiet, "No progress bar");
    cmd->callback([c] { run(*c); });
}

}  // namespace vdblight::app
