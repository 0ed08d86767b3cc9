// vdblight_bench_shadow_edges: where the shadow edges' rays go, and what the lattice's skipping
// saves (issue 32; bake/shadow_edge_lattice.h). On the accuracy benchmark's four scenes at the
// default bake's grid (~16384 nodes) and lights (--direct occlusion, at most 4 listed):
//  - the visibility channels alone (bake --no-shadow-edges): CPU seconds and rays;
//  - the edges as the bake finds them (bakeShadowEdgesOnLattice): CPU seconds, rays, searches;
//  - the reference, findShadowEdge at every node and light: CPU seconds, rays, and where they
//    go (nodes whose search found an edge in range, or none, lit or shadowed);
//  - the two volumes' lookups at random points of the node box: the largest visibility
//    difference and how many points differ by more than 0.01, per kind of light.
// --quick: 1/8 of the nodes. --scene NAME: one scene; --file SCENE: a scene file instead. --at X,Y,Z:
// the cell around a point.
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "accuracy_scenes.h"
#include "bake/parallel_nodes.h"
#include "bake/shadow_edge_lattice.h"
#include "bake/shadow_edge_search.h"
#include "basis/shadow_edges.h"
#include "bench_args.h"
#include "query/light_visibility.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/query/query.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/trace/trace.h"

using namespace vdblight;

namespace {

double cpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

const char* kindName(DirectLight::Kind k) {
    switch (k) {
        case DirectLight::Kind::Polygon: return "polygon";
        case DirectLight::Kind::Mesh: return "mesh";
        case DirectLight::Kind::Directional: return "directional";
        case DirectLight::Kind::Spot: return "spot";
        default: return "point";
    }
}

/// The reference: findShadowEdge at every node and light, with where its rays go.
void referenceEdges(const Scene& scene, const Tracer& tracer, const DirectPlan& plan, VolumeLevel& level, int threads) {
    const std::size_t lights = plan.lights.size();
    std::vector<RayCount> perItem(level.grid.nodeCount() * lights);
    const double c0 = cpuSeconds();
    bake_detail::forEachItemInParallel(level.grid.nodeCount(), threads, nullptr, [&](std::size_t n, RayCount& rays) {
        for (std::size_t l = 0; l < lights; ++l) {
            RayCount mine;
            const bake_detail::ShadowEdge e =
                bake_detail::findShadowEdge(scene, tracer, plan.lights[l], Vec3f(level.grid.node(n)), level.grid.spacing, mine);
            bake_detail::storeShadowEdge(e, &level.lightShadowEdges[(n * lights + l) * shadow_edge::kFloatsPerLight]);
            perItem[n * lights + l] = mine;
            rays += mine;
        }
    });
    const double cpu = cpuSeconds() - c0;
    // Where the rays go: pairs whose search found an edge in range, and those that found none.
    uint64_t found = 0, lit = 0, shadowed = 0, raysFound = 0, raysNone = 0, total = 0;
    for (std::size_t p = 0; p < perItem.size(); ++p) {
        const float d = level.lightShadowEdges[p * shadow_edge::kFloatsPerLight];
        const uint64_t r = perItem[p].total();
        total += r;
        if (std::abs(d) < shadow_edge::kRange) ++found, raysFound += r;
        else (d > 0 ? lit : shadowed) += 1, raysNone += r;
    }
    const double pairs = double(perItem.size());
    std::printf("  reference (findShadowEdge everywhere): CPU %.2f s, %llu rays (%.1f per node and light)\n", cpu,
                (unsigned long long)total, total / pairs);
    std::printf("    edge found in range: %.1f %% of pairs, %.1f rays each; none: lit %.1f %%, shadowed %.1f %%, %.1f rays each\n",
                100.0 * found / pairs, found ? double(raysFound) / found : 0.0, 100.0 * lit / pairs, 100.0 * shadowed / pairs,
                lit + shadowed ? double(raysNone) / double(lit + shadowed) : 0.0);
}

/// The largest difference between two volumes' looked-up visibility, per light, at random points.
void compareLookups(const Volume& fast, const Volume& reference, const DirectPlan& plan) {
    const IrradianceQuery a(fast), b(reference);
    const auto& va = dynamic_cast<const LightVisibility&>(a.lookup());
    const auto& vb = dynamic_cast<const LightVisibility&>(b.lookup());
    const Bounds box = fast.levels[0].grid.nodeBounds();
    const std::size_t lights = plan.lights.size();
    std::vector<double> worst(lights, 0.0);
    std::vector<int> over(lights, 0);
    Rng rng(17);
    const int points = 20000;
    std::vector<float> fa(lights), fb(lights);
    for (int i = 0; i < points; ++i) {
        const Vec3d x = box.lo + (box.hi - box.lo) * Vec3d(rng.uniform(), rng.uniform(), rng.uniform());
        va.visibility(x, fa.data());
        vb.visibility(x, fb.data());
        for (std::size_t l = 0; l < lights; ++l) {
            const double d = std::abs(double(fa[l]) - double(fb[l]));
            worst[l] = std::max(worst[l], d);
            if (d > 0.01) ++over[l];
        }
    }
    for (std::size_t l = 0; l < lights; ++l)
        std::printf("  light %zu (%s): lookups at %d points, max |difference| %.2g, %d points beyond 0.01\n", l,
                    kindName(plan.lights[l].light.kind), points, worst[l], over[l]);
}

/// Against the truth, for the hard lights (point, spot, directional), whose visibility at a point
/// is its centre ray's answer: at random points of the node box, how many lookups are off by
/// more than 0.5 (on the wrong side of an edge) and the mean |error|, for each volume given.
void compareWithTruth(const Tracer& tracer, const DirectPlan& plan, const std::vector<std::pair<const char*, const Volume*>>& volumes) {
    const Bounds box = volumes.front().second->levels[0].grid.nodeBounds();
    const std::size_t lights = plan.lights.size();
    for (std::size_t l = 0; l < lights; ++l) {
        const DirectLight::Kind kind = plan.lights[l].light.kind;
        if (kind == DirectLight::Kind::Polygon || kind == DirectLight::Kind::Mesh) continue;
        std::printf("  light %zu (%s) against its centre ray at 20000 points:", l, kindName(kind));
        for (const auto& [name, volume] : volumes) {
            const IrradianceQuery q(*volume);
            const auto& lookup = dynamic_cast<const LightVisibility&>(q.lookup());
            Rng rng(23);
            std::vector<float> v(lights);
            int wrong = 0;
            double sum = 0;
            const int points = 20000;
            for (int i = 0; i < points; ++i) {
                const Vec3d x = box.lo + (box.hi - box.lo) * Vec3d(rng.uniform(), rng.uniform(), rng.uniform());
                lookup.visibility(x, v.data());
                RayCount rays;
                const float truth = bake_detail::centreRayBlocked(tracer, plan.lights[l], Vec3f(x), rays) ? 0.0f : 1.0f;
                const double e = std::abs(double(v[l]) - truth);
                sum += e;
                wrong += e > 0.5;
            }
            std::printf(" %s %d wrong side, mean |error| %.4f;", name, wrong, sum / points);
        }
        std::printf("\n");
    }
}

/// --at X,Y,Z: the cell around a point, corner by corner (what the lookup blends), and the
/// centre ray's answer at the point itself.
void printCell(const Scene& scene, const Tracer& tracer, const DirectPlan& plan, const Volume& v, const Vec3d& x) {
    const VolumeLevel& level = v.levels[0];
    const GridSpec& g = level.grid;
    const std::size_t lights = plan.lights.size();
    const Vec3d u = (x - g.origin) / g.spacing;
    const int i0 = std::clamp(int(std::floor(u.x)), 0, g.nx - 2), j0 = std::clamp(int(std::floor(u.y)), 0, g.ny - 2),
              k0 = std::clamp(int(std::floor(u.z)), 0, g.nz - 2);
    std::printf("  at (%.3f, %.3f, %.3f): cell (%d, %d, %d), offsets (%.2f, %.2f, %.2f)\n", x.x, x.y, x.z, i0, j0, k0, u.x - i0,
                u.y - j0, u.z - k0);
    const IrradianceQuery q(v);
    std::vector<float> looked(lights);
    dynamic_cast<const LightVisibility&>(q.lookup()).visibility(x, looked.data());
    for (std::size_t l = 0; l < lights; ++l) {
        RayCount rays;
        const bake_detail::ShadowEdge here = bake_detail::findShadowEdge(scene, tracer, plan.lights[l], Vec3f(x), g.spacing, rays);
        std::printf("  light %zu: looked-up visibility %.3f; at the point itself: centre ray %s, its edge d %.3f w %.3f\n", l,
                    looked[l], bake_detail::centreRayBlocked(tracer, plan.lights[l], Vec3f(x), rays) ? "blocked" : "free",
                    here.distance, here.width);
        for (int c = 0; c < 8; ++c) {
            const int i = i0 + (c & 1), j = j0 + ((c >> 1) & 1), k = k0 + ((c >> 2) & 1);
            const std::size_t n = g.index(i, j, k);
            const float* e = &level.lightShadowEdges[(n * lights + l) * shadow_edge::kFloatsPerLight];
            const Vec3d p = g.node(i, j, k);
            const DirectLight& dl = plan.lights[l].light;
            const Vec3f towards = dl.kind == DirectLight::Kind::Directional ? -Vec3f(dl.direction) : Vec3f(dl.position) - Vec3f(p);
            const Hit h = tracer.intersect(Ray{Vec3f(p), normalize(towards)});
            const Vec3f at = Vec3f(p) + normalize(towards) * h.t;
            std::printf("    corner (%d, %d, %d) at (%.2f, %.2f, %.2f): visibility %.3f, d %.3f, w %.3f, far %.3f; towards the light: %s "
                        "(%.2f, %.2f, %.2f)\n", i, j, k, p.x, p.y, p.z, level.lightVisibility[n * lights + l], e[0], e[1],
                        e[shadow_edge::kFar],
                        h.hit() ? "hits" : "free", h.hit() ? at.x : 0.0f, h.hit() ? at.y : 0.0f, h.hit() ? at.z : 0.0f);
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    bench::BenchArgs args("vdblight_bench_shadow_edges", {{"--scene", "NAME"}, {"--file", "SCENE"}, {"--threads", "N"}, {"--at", "X,Y,Z"}});
    if (!args.parse(argc, argv)) return 1;
    const bool quick = args.quick();
    const int threads = args.integer("--threads", 2);
    const std::string only = args.text("--scene");
    std::vector<bench::AccuracyScene> scenes;
    if (args.given("--file")) {  // a scene file instead (e.g. data/cornell_box.obj, the default scene)
        scenes.push_back({args.text("--file"), loadScene(args.text("--file")), 1, {}});
    } else {
        scenes = bench::accuracyScenes();
    }
    for (bench::AccuracyScene& as : scenes) {
        if (!only.empty() && as.name.rfind(only, 0) != 0) continue;
        const Tracer tracer(as.scene);
        GridPlacement gp;
        gp.spacing = spacingForNodeBudget(as.scene.bounds(), quick ? 16384 / 8 : 16384);
        const GridSpec grid = placeUniformGrid(as.scene.bounds(), gp, 1);
        DirectOptions o;
        o.mode = DirectMode::Occlusion;
        o.threads = threads;
        const DirectPlan plan = planDirectLight(as.scene, tracer, grid, o);
        std::printf("%s: %zu nodes (%d x %d x %d), %zu listed lights\n", as.name.c_str(), grid.nodeCount(), grid.nx, grid.ny,
                    grid.nz, plan.lights.size());
        // The visibility channels alone, then the bake's edges over them.
        Volume fast = bake_detail::emptyShVolume(grid);
        o.shadowEdges = false;
        double c0 = cpuSeconds();
        bakeLightVisibility(as.scene, tracer, plan, o, fast);
        const double channels = cpuSeconds() - c0;
        const int64_t channelRays = std::get<int64_t>(fast.meta.at("direct_visibility_rays"));
        VolumeLevel& level = fast.levels[0];
        const std::size_t lights = plan.lights.size();
        level.lightShadowEdges.assign(level.heldNodes() * lights * shadow_edge::kFloatsPerLight, 0.0f);
        c0 = cpuSeconds();
        const bake_detail::EdgeLatticeRun run = bake_detail::bakeShadowEdgesOnLattice(
            as.scene, tracer, plan.lights, level, {},
            [&](std::size_t n, std::size_t l, RayCount&) { return level.lightVisibility[n * lights + l]; }, threads, nullptr);
        const double edges = cpuSeconds() - c0;
        std::printf("  visibility channels alone: CPU %.2f s, %lld rays\n", channels, (long long)channelRays);
        std::printf("  edges as baked (lattice): CPU %.2f s, %llu rays; searched %llu of %llu node-light pairs (%.1f %%)\n", edges,
                    (unsigned long long)run.rays.total(), (unsigned long long)run.searched,
                    (unsigned long long)(run.searched + run.skipped), 100.0 * run.searched / double(run.searched + run.skipped));
        Volume reference = fast;
        referenceEdges(as.scene, tracer, plan, reference.levels[0], threads);
        compareLookups(fast, reference, plan);
        Volume trilinear = fast;
        trilinear.levels[0].lightShadowEdges.clear();
        Volume oneEdge = fast;  // the lookup before the second edge (bit for bit: shadow_edges.h)
        for (std::size_t p = 0; p < oneEdge.levels[0].lightShadowEdges.size(); p += shadow_edge::kFloatsPerLight)
            oneEdge.levels[0].lightShadowEdges[p + shadow_edge::kFar] = 0.0f;
        compareWithTruth(tracer, plan,
                         {{"trilinear", &trilinear}, {"one edge", &oneEdge}, {"as baked", &fast}, {"searched everywhere", &reference}});
        if (args.given("--at")) {
            Vec3d x;
            if (std::sscanf(args.text("--at").c_str(), "%lf,%lf,%lf", &x.x, &x.y, &x.z) != 3) return 1;
            printCell(as.scene, tracer, plan, fast, x);
        }
    }
    return 0;
}
