// vdblight prt bake|relight|info: precomputed radiance transfer for moving lights
// (Leonhardt & Bohn). Options are parsed into structs; the work is in vdblight/prt.h.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>

#include "app_common.h"
#include "commands.h"
#include "vdblight/core/errors.h"
#include "vdblight/prt/prt.h"
#include "vdblight/scene/scene.h"
#include "vdblight/light/light.h"
#include "vdblight/trace/trace.h"
#include "vdblight/volume/vdb_io.h"

namespace vdblight::app {

namespace {

struct PrtBakeCommand {
    SceneOptions scene;  // path, --scale, --up
    std::string output;
    PrtOptions options;
    PrtWriteOptions write;
    std::string formFactors = "auto";
    bool noQuantize = false;
    bool quiet = false;
};

struct PrtRelightCommand {
    std::string input;
    std::vector<std::string> lights;
    std::vector<std::string> areaLights;
    std::string scene;  ///< the baked scene: lights' direct light in the volume, inside-solid test
    bool sceneLights = false;  ///< relight with the lights of --scene (sceneLights)
    bool indirectOnly = false;
    float areaSize = 0;
    int areaSamples = 5;
    std::string output;
    std::string format;  ///< csv | ply (default from the extension)
    std::string referenceScene;
    SceneOptions frame;  ///< --scale, --up for --scene and --reference
    std::string volumeOutput;
    int threads = 0;
    bool quiet = false;
};

double seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void runBake(PrtBakeCommand& c) {
    if (c.formFactors == "auto") c.options.formFactors = PrtOptions::FormFactors::Auto;
    else if (c.formFactors == "dense") c.options.formFactors = PrtOptions::FormFactors::Dense;
    else if (c.formFactors == "sampled") c.options.formFactors = PrtOptions::FormFactors::Sampled;
    else throw ValueError("--form-factors must be auto, dense or sampled (got '" + c.formFactors + "')");
    checkOutputWritable(c.output);
    const Scene scene = loadSceneFile(c.scene.path.empty() ? defaultScenePath() : c.scene.path, c.scene, c.quiet);
    const Tracer tracer(scene);
    c.write.quantize = !c.noQuantize;
    ProgressBar progress(c.quiet);
    const PrtData prt = bakePrt(scene, tracer, c.options, &progress);
    writePrt(prt, c.output, c.write);
    if (c.quiet) return;
    const PrtFileInfo info = inspectPrt(c.output);
    std::cout << "prt bake: " << prt.samples.size() << " samples (radius " << prt.samples.radius << "), "
              << prt.samples.clusters() << " clusters, " << prt.visGrid * prt.visGrid << " visibility directions -> "
              << prt.visCoeffStride << " coefficients, " << prt.trainLights << " training lights -> "
              << prt.transferStride - 1 << " basis vectors\n"
              << "time: samples " << formatSeconds(prt.secondsSamples) << ", visibility "
              << formatSeconds(prt.secondsVisibility) << ", basis " << formatSeconds(prt.secondsBasis)
              << ", transfer " << formatSeconds(prt.secondsTransfer) << "\n"
              << "storage: " << formatBytes(double(info.bytesFloat32)) << " as dense 32-bit floats, "
              << formatBytes(double(info.bytesStored)) << " stored, file " << formatBytes(double(info.fileBytes))
              << " (" << c.output << ")\n";
}

void runRelight(const PrtRelightCommand& c) {
    if (c.sceneLights && c.scene.empty()) throw ValueError("--scene-lights needs --scene (the scene whose lights to use)");
    if (c.lights.empty() && c.areaLights.empty() && !c.sceneLights) {
        throw ValueError("give at least one --light x,y,z[,r,g,b], --area-light or --scene-lights");
    }
    std::vector<PrtLightSpec> parsed;
    for (const std::string& t : c.lights) parsed.push_back(parsePointLightSpec(t, c.areaSize, c.areaSamples));
    for (const std::string& t : c.areaLights) parsed.push_back(parseAreaLightSpec(t));
    bool ply = c.format == "ply";
    if (c.format.empty()) ply = c.output.size() > 4 && c.output.substr(c.output.size() - 4) == ".ply";
    else if (c.format != "csv" && c.format != "ply") throw ValueError("--format must be csv or ply");
    if (!c.output.empty()) checkOutputWritable(c.output);
    if (!c.volumeOutput.empty()) checkOutputWritable(c.volumeOutput);
    const PrtData prt = readPrt(c.input);
    std::vector<DirectLight> lights;  // in the file's local frame (the scene's, scene_origin.h)
    for (const PrtLightSpec& p : parsed)
        for (DirectLight l : p.lights) {
            l.translate(Vec3d(0, 0, 0) - prt.origin);
            lights.push_back(l);
        }
    if (!c.volumeOutput.empty() && !prt.hasVolume()) {
        throw ValueError("'" + c.input + "' has no volume: bake it with --volume-resolution to use --volume-out");
    }
    if (!c.volumeOutput.empty() && !c.indirectOnly && c.scene.empty()) {
        throw ValueError("--volume-out needs --scene (the baked scene, for the lights' direct light at the nodes), "
                         "or --indirect-only");
    }
    std::unique_ptr<Scene> scene;
    std::unique_ptr<Tracer> tracer;
    if (!c.scene.empty()) {
        scene = std::make_unique<Scene>(loadSceneFile(c.scene, c.frame, c.quiet));
        if (scene->contentHash() != prt.sceneHash) {
            throw ValueError("--scene '" + c.scene + "' is not the scene '" + c.input + "' was baked from");
        }
        tracer = std::make_unique<Tracer>(*scene);
    }
    if (c.sceneLights) {  // the scene's own lights, already in its local frame
        const std::size_t before = lights.size();
        for (const SceneLight& l : sceneLights(*scene)) lights.push_back(l.light);
        if (lights.size() == before) throw ValueError("--scene-lights: '" + c.scene + "' has no lights");
    }
    for (std::size_t i = 0; i < parsed.size(); ++i) {
        const std::string why = prtLightWarning(prt, tracer.get(), parsed[i].world);
        if (!why.empty()) std::cerr << "vdblight: warning: light " << i + 1 << " at " << why << "\n";
    }
    PrtRelightOptions options;
    options.areaSamples = c.areaSamples;
    options.threads = c.threads;
    const double t0 = seconds();
    const PrtLighting lit = relightPrt(prt, lights, options);
    const double t1 = seconds();
    if (!c.quiet) {
        std::cerr << "prt relight: " << prt.samples.size() << " samples, " << lights.size() << " light(s) in "
                  << formatSeconds(t1 - t0) << "\n";
    }
    if (!c.referenceScene.empty()) {
        // Ground truth: exact direct light by shadow rays, uncompressed one-bounce transfer.
        const Scene scene = loadSceneFile(c.referenceScene, c.frame, c.quiet);
        if (scene.contentHash() != prt.sceneHash) {
            std::cerr << "vdblight: warning: --reference scene differs from the baked one\n";
        }
        const Tracer tracer(scene);
        const PrtReferenceErrors e = prtReferenceErrors(prt, lit, lights, scene, tracer, c.threads);
        std::cerr << "reference: RMS relative error direct " << e.direct << ", indirect " << e.indirect << "\n";
    }
    if (!c.volumeOutput.empty()) {
        const double v0 = seconds();
        const bool direct = !c.indirectOnly && scene;
        const Volume volume = relightVolume(prt, lights, direct ? scene.get() : nullptr, direct ? tracer.get() : nullptr,
                                            options);
        const double v1 = seconds();
        writeVolume(volume, c.volumeOutput);
        if (!c.quiet) {
            std::cerr << "prt relight: volume of " << prt.volumeGrid.nodeCount() << " nodes in "
                      << formatSeconds(v1 - v0) << " -> " << c.volumeOutput << "\n";
        }
    }
    emitText(c.output, prtLightingTable(prt, lit, ply));
}

}  // namespace

void printPrtInfo(const std::string& path) { std::cout << prtInfoText(path); }

void addPrtCommand(CLI::App& app) {
    CLI::App* prt = app.add_subcommand("prt", "Precomputed radiance transfer for moving lights (Leonhardt & Bohn)");
    prt->require_subcommand(1);

    auto b = std::make_shared<PrtBakeCommand>();
    CLI::App* bake = prt->add_subcommand("bake", "Samples, compressed visibility, direct-light basis and transfer");
    addSceneFileOptions(*bake, b->scene);
    bake->add_option("-o,--output", b->output, "PRT file to write (.vdb)")->required();
    bake->add_option("--samples", b->options.samples, "Target number of surface samples")->capture_default_str();
    bake->add_option("--sample-radius", b->options.sampleRadius, "Poisson-disk radius (overrides --samples)");
    bake->add_option("--cluster-size", b->options.clusterSize, "Samples per cluster (about)")->capture_default_str();
    bake->add_option("--vis-dirs", b->options.visDirs, "Hemisphere directions per depth buffer")->capture_default_str();
    bake->add_option("--vis-coeffs", b->options.visCoeffs, "PCA coefficients kept per depth buffer")->capture_default_str();
    bake->add_option("--train-lights", b->options.trainLights, "Example point lights for the basis")->capture_default_str();
    bake->add_option("--transfer-coeffs", b->options.transferCoeffs, "Direct-light basis vectors per cluster")
        ->capture_default_str();
    bake->add_option("--sparse-threshold", b->write.sparseThreshold,
                     "Drop matrix entries below this fraction of their row's largest")->capture_default_str();
    bake->add_option("--volume-resolution", b->options.volumeResolution,
                     "Also make an SH volume with this many nodes along the longest axis relightable");
    bake->add_option("--bounces", b->options.bounces, "Diffuse bounces in the transfer (1 = the paper's one)")
        ->capture_default_str();
    bake->add_flag("--raw-form-factors", [b](int64_t) { b->options.closureNormalise = false; },
                   "Do not rescale form factors to the hemisphere that rays find covered");
    bake->add_option("--form-factors", b->formFactors,
                     "dense: every sample pair (n^2 rays and floats); sampled: --form-factor-rays rays per "
                     "receiver (scales to 45 k samples); auto: dense up to " +
                         std::to_string(PrtOptions::kDenseFormFactorLimit) + " samples")
        ->capture_default_str();
    bake->add_option("--form-factor-rays", b->options.formFactorRays,
                     "Rays per sample / node for sampled form factors")->capture_default_str();
    bake->add_option("--oriented-training", b->options.orientedTraining,
                     "One-sided example lights per point light in the direct-light basis (0: point lights only)")
        ->capture_default_str();
    bake->add_option("--oriented-coeffs", b->options.orientedCoeffs,
                     "Basis vectors per cluster added from the one-sided example lights")->capture_default_str();
    bake->add_flag("--paper-basis", b->options.paperBasis,
                   "Direct-light basis exactly as the paper's eq. 7 (centred, unnormalised examples)");
    bake->add_flag("--no-quantize", b->noQuantize, "Store 32-bit floats instead of 16-bit");
    bake->add_option("--seed", b->options.seed, "Random seed")->capture_default_str();
    bake->add_option("--threads", b->options.threads, "Worker threads (0 = all cores)")->capture_default_str();
    bake->add_flag("-q,--quiet", b->quiet, "No progress or summary");
    bake->callback([b] { runBake(*b); });

    auto r = std::make_shared<PrtRelightCommand>();
    CLI::App* relight = prt->add_subcommand("relight", "Per-sample direct and indirect light for new light positions");
    relight->add_option("file", r->input, "PRT file from 'prt bake'")->required();
    relight->add_option("--light", r->lights, "Point light x,y,z[,r,g,b] (intensity W/sr; repeatable)");
    relight->add_option("--area-light", r->areaLights,
                        "Square area light x,y,z,nx,ny,nz,size[,r,g,b]: centre, emitting side, side length, "
                        "intensity along the normal (repeatable)");
    relight->add_option("--scene", r->scene,
                        "The baked scene: the lights' visibility in --volume-out (a --direct occlusion volume) and "
                        "the exact inside-a-solid test");
    relight->add_flag("--scene-lights", r->sceneLights,
                      "Relight with the lights of --scene too (emissive polygons, point and spot lights; a "
                      "directional light is refused)");
    addSceneFrameOptions(*relight, r->frame);  // load --scene and --reference as the bake did
    relight->add_flag("--indirect-only", r->indirectOnly, "--volume-out holds only the reflected light (no --scene needed)");
    relight->add_option("--area-size", r->areaSize, "Make every --light an isotropic square of this side (XZ plane)");
    relight->add_option("--area-samples", r->areaSamples,
                        "Points per side of an area light (--area-light, --area-size, polygon lights of the scene)")
        ->check(CLI::Range(1, 64))->capture_default_str();
    relight->add_option("-o,--output", r->output, "Write CSV or PLY here instead of stdout");
    relight->add_option("--format", r->format, "csv or ply (default: from the extension, else csv)");
    relight->add_option("--reference", r->referenceScene,
                        "Scene to compute the exact direct and uncompressed one-bounce light from; prints the errors");
    relight->add_option("--volume-out", r->volumeOutput,
                        "Write the relit SH volume (.vdb: reflected radiance in the SH, the lights' direct light as "
                        "in a --direct occlusion bake; needs a bake with --volume-resolution and --scene or "
                        "--indirect-only)");
    relight->add_option("--threads", r->threads, "Worker threads for --reference and the visibility of --volume-out (0 = all cores)");
    relight->add_flag("-q,--quiet", r->quiet, "No timing line");
    relight->callback([r] { runRelight(*r); });

    auto path = std::make_shared<std::string>();
    CLI::App* info = prt->add_subcommand("info", "Describe a PRT file: sizes before and after compression");
    info->add_option("file", *path, "PRT file")->required();
    info->callback([path] { printPrtInfo(*path); });
}

}  // namespace vdblight::app
