// The photon pass against closed forms for punctual lights, and against `reference` on the
// default scene.
//
// With the flux estimator, <I_delta, delta> at a node is the flux through the node's dual
// face divided by its area A (photons.h). For a point light of intensity I that flux is
// I * Omega, Omega the solid angle the face subtends from the light (closed form for a
// rectangle); for a spot light it is the integral of I f(cos) cos / r^2 over the face (f the
// glTF falloff), integrated here by a fine midpoint rule. Only the delta facing the light
// receives anything; the others are exactly zero.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "grids.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/reference/reference.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "vdblight/query/query.h"

using namespace vdblight;

namespace {
// Embree needs a triangle: a tiny black one far from the grid and the light.
Scene emptySpace() {
    Scene s;
    s.name = "empty";
    Material m;
    m.albedo = {0, 0, 0};
    const uint32_t id = addMaterial(s, m);
    const Vec3f at(-3, -3, -3);
    addTriangle(s, at, at + Vec3f(1e-3f, 0, 0), at + Vec3f(0, 1e-3f, 0), id);
    return s;
}

GridSpec grid4() { return test::makeGrid({0, 0, 0}, 0.25, 4, 4, 4); }

Volume bake(const Scene& s, const GridSpec& g, uint64_t photons) {
    const Tracer tracer(s);
    PhotonOptions o;
    o.photons = photons;
    return bakePhotons(s, tracer, g, o);
}

/// The dual face of node (i, j, k) in the plane normal to axis a: its extent along the other
/// two axes b = (a + 1) % 3, c = (a + 2) % 3, clipped by the node box.
struct Face {
    double plane;           // coordinate along a
    double lo[2], hi[2];    // along b, c
    double area() const { return (hi[0] - lo[0]) * (hi[1] - lo[1]); }
};

Face dualFace(const GridSpec& g, int a, const int idx[3]) {
    const int dims[3] = {g.nx, g.ny, g.nz};
    Face f;
    f.plane = g.origin[a] + idx[a] * g.spacing;
    for (int s = 0; s < 2; ++s) {
        const int b = (a + 1 + s) % 3;
        const double centre = g.origin[b] + idx[b] * g.spacing;
        f.lo[s] = std::max(centre - 0.5 * g.spacing, g.origin[b]);
        f.hi[s] = std::min(centre + 0.5 * g.spacing, g.origin[b] + (dims[b] - 1) * g.spacing);
    }
    return f;
}

/// Solid angle of an axis-aligned rectangle seen from p (exact): with (u, v) the in-plane
/// offsets from the foot of the perpendicular and h the distance to the plane,
/// Omega = sum of +-atan(u v / (h sqrt(h^2 + u^2 + v^2))) over the corners.
double solidAngle(const Face& f, int a, const Vec3d& p) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const double h = std::abs(f.plane - p[a]);
    auto F = [&](double u, double v) { return std::atan(u * v / (h * std::sqrt(h * h + u * u + v * v))); };
    const double u0 = f.lo[0] - p[b], u1 = f.hi[0] - p[b], v0 = f.lo[1] - p[c], v1 = f.hi[1] - p[c];
    return F(u1, v1) - F(u0, v1) - F(u1, v0) + F(u0, v0);
}

/// Direction delta of axis a that faces a light at p from the plane of the face.
int facingDelta(int a, double plane, const Vec3d& p) { return iv::direction(a, p[a] < plane); }

Vec3d vectorAt(const Volume& v, std::size_t node, int d, int c) {
    const float* q = v.levels[0].nodeData(node, iv::kChannels) + 3 * iv::channel(d, c);
    return {q[0], q[1], q[2]};
}
double axisComponent(const Vec3d& v, int d) { return d % 2 ? -v[d / 2] : v[d / 2]; }

/// Checks every node and delta of `v` against expected(a, face) = <I_delta, delta> / colour
/// for the delta facing the light at p, zero for the other. Prints and bounds the mean and
/// worst ratios over faces that receive at least `minShare` of the largest expected value.
template <typename Expected>
void checkAgainst(const Volume& v, const GridSpec& g, const Vec3d& p, const Rgb& colour, Expected&& expected,
                  double minShare, double meanTol, double worstTol, const char* what) {
    double sum = 0, worst = 0, largest = 0;
    int count = 0;
    std::vector<double> want(g.nodeCount() * 3);
    for (int pass = 0; pass < 2; ++pass)
        for (int k = 0; k < g.nz; ++k)
            for (int j = 0; j < g.ny; ++j)
                for (int i = 0; i < g.nx; ++i) {
                    const int idx[3] = {i, j, k};
                    const std::size_t node = g.index(i, j, k);
                    for (int a = 0; a < 3; ++a) {
                        const Face f = dualFace(g, a, idx);
                        if (pass == 0) {
                            want[node * 3 + a] = expected(a, f);
                            largest = std::max(largest, want[node * 3 + a]);
                            continue;
                        }
                        const int lit = facingDelta(a, f.plane, p), dark = lit ^ 1;
                        for (int c = 0; c < 3; ++c) {
                            const Vec3d off = vectorAt(v, node, dark, c);
                            ASSERT_EQ(off.x, 0.0) << what << " node " << node << " delta " << dark;
                            ASSERT_EQ(off.y, 0.0);
                            ASSERT_EQ(off.z, 0.0);
                            const double e = want[node * 3 + a] * colour[c];
                            const double got = axisComponent(vectorAt(v, node, lit, c), lit);
                            if (want[node * 3 + a] < minShare * largest) {
                                EXPECT_LE(got, 2 * minShare * largest * colour[c] + 1e-12) << what << " node " << node;
                                continue;
                            }
                            const double ratio = got / e;
                            sum += ratio, ++count;
                            worst = std::max(worst, std::abs(ratio - 1));
                        }
                    }
                }
    std::printf("%s: %d lit faces x colours, mean <I,delta>/closed form %.4f, worst %.4f\n", what, count, sum / count,
                worst);
    EXPECT_GT(count, 0);
    EXPECT_NEAR(sum / count, 1.0, meanTol) << what;
    EXPECT_LT(worst, worstTol) << what;
}
}  // namespace

// A point light above and beside a 4 x 4 x 4 grid: every face gets I * Omega / A exactly in
// expectation (boundary faces included, with their halved and quartered areas).
TEST(PhotonPunctual, PointLightMatchesTheSolidAngleOfEveryDualFace) {
    Scene s = emptySpace();
    const Vec3d p(0.37, 1.3, 0.29);
    const Rgb intensity{3.0f, 2.0f, 1.0f};
    s.pointLights.push_back({Vec3f(p), intensity});
    const GridSpec g = grid4();
    const Volume v = bake(s, g, 1 << 22);
    checkAgainst(
        v, g, p, intensity, [&](int a, const Face& f) { return solidAngle(f, a, p) / f.area(); }, 0.05, 0.01, 0.08,
        "point light");
    // The vector at a node points at the light (it averages the directions over the face).
    const std::size_t node = g.index(1, 3, 1);
    const Vec3d got = vectorAt(v, node, iv::direction(1, false), 0);
    const Vec3d towards = normalize(p - g.node(1, 3, 1));
    EXPECT_GT(dot(normalize(got), towards), std::cos(5.0 * kPi / 180)) << "more than 5 degrees off";
}

// A spot light pointing down into the grid, with a falloff ramp and a cut-off that crosses it:
// the +y faces get the integral of I f cos / r^2 over the face; nothing outside the cone.
TEST(PhotonPunctual, SpotLightMatchesItsConeAndFalloff) {
    Scene s = emptySpace();
    const Vec3d p(0.375, 1.5, 0.375);
    const Rgb intensity{2.0f, 1.0f, 0.5f};
    SpotLight spot;
    spot.position = Vec3f(p);
    spot.direction = {0, -1, 0};
    spot.intensity = intensity;
    spot.innerConeAngle = 0.15f;
    spot.outerConeAngle = 0.35f;
    s.spotLights.push_back(spot);
    const GridSpec g = grid4();
    const Volume v = bake(s, g, 1 << 20);
    const double cosInner = std::cos(double(spot.innerConeAngle)), cosOuter = std::cos(double(spot.outerConeAngle));
    auto falloff = [&](double c) {
        if (c <= cosOuter) return 0.0;
        const double t = std::min(1.0, (c - cosOuter) / (cosInner - cosOuter));
        return t * t;
    };
    // Flux / area through a face, midpoint rule on 200 x 200 cells.
    auto expected = [&](int a, const Face& f) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        const int n = 200;
        double sum = 0;
        for (int u = 0; u < n; ++u)
            for (int w = 0; w < n; ++w) {
                Vec3d x;
                x[a] = f.plane;
                x[b] = f.lo[0] + (u + 0.5) / n * (f.hi[0] - f.lo[0]);
                x[c] = f.lo[1] + (w + 0.5) / n * (f.hi[1] - f.lo[1]);
                const Vec3d r = x - p;
                const double d2 = dot(r, r), d = std::sqrt(d2);
                const double cosAxis = -r.y / d;             // angle to the spot's axis (0, -1, 0)
                const double cosFace = std::abs(r[a]) / d;   // angle to the face's normal
                sum += falloff(cosAxis) * cosFace / d2;
            }
        return sum / (n * n);  // the mean over the face: flux / (I A)
    };
    checkAgainst(v, g, p, intensity, expected, 0.02, 0.01, 0.08, "spot light");
    // The corner columns lie outside the cone (angle > outer) from every point of their
    // upper faces: exactly nothing.
    for (int j = 0; j < g.ny; ++j) {
        const Vec3d top = vectorAt(v, g.index(0, j, 0), iv::direction(1, false), 0);
        if (expected(1, dualFace(g, 1, std::array<int, 3>{0, j, 0}.data())) == 0.0) {
            EXPECT_EQ(top.y, 0.0) << "node (0, " << j << ", 0) lies outside the cone";
        }
    }
}

// The default scene against `reference` at random free-space points: the relative RMS error
// and the bias (mean signed error over mean) of luminance, printed and bounded, for random
// normals and for the nearest axis normals, with the default (quadratic) blend; for axis
// normals both blends are exact and the error is spatial interpolation and noise. The paper's
// n^2 blend is measured beside it: for random normals it is biased low whatever the photon
// count (a lower bound of E; under a uniform sky pi L sum |n_a|^3, 0.58 pi L for
// n = (1, 1, 1) / sqrt(3)). Measured with the paper's blend before issue 15, trilinear /
// tricubic: 0.27 / 0.26 random, 0.16 / 0.13 axis (the same at 500 k and 8 M photons); with
// the default (bounded) blend: 0.16 / 0.13 random, bias -0.7 % (the paper's -25 % failed it).
TEST(PhotonReference, DefaultSceneRmsErrorAtRandomFreeSpacePoints) {
    const Scene scene = loadScene(defaultScenePath());
    const Tracer tracer(scene);
    GridPlacement placement;
    placement.resolution = 10;
    const GridSpec g = placeUniformGrid(scene.bounds(), placement, 1);
    PhotonOptions o;
    o.photons = 2'000'000;
    const Volume v = bakePhotons(scene, tracer, g, o);

    Rng rng(99);
    const Bounds box = g.nodeBounds();
    const int count = 1400;
    std::vector<ReferencePoint> points;  // [0, count): random normals; [count, 2 count): nearest axes
    for (int i = 0; i < count; ++i)
        points.push_back({Vec3f(box.lo + box.size() * Vec3d(rng.uniform(), rng.uniform(), rng.uniform())),
                          uniformSphere(rng.uniform(), rng.uniform())});
    for (int i = 0; i < count; ++i) {
        const Vec3f n = points[i].normal;
        int a = 0;
        for (int b = 1; b < 3; ++b)
            if (std::abs(n[b]) > std::abs(n[a])) a = b;
        Vec3f axis(0, 0, 0);
        axis[a] = n[a] > 0 ? 1.0f : -1.0f;
        points.push_back({points[i].position, axis});
    }
    ReferenceOptions ro;
    ro.samples = 1024;
    const std::vector<ReferenceResult> ref = referenceIrradiance(scene, tracer, points, ro);
    const VectorGridLookup lin(v, OutsidePolicy::Clamp, Interpolation::Trilinear);
    const VectorGridLookup cub(v, OutsidePolicy::Clamp, Interpolation::Tricubic);
    const VectorGridLookup paper(v, OutsidePolicy::Clamp, Interpolation::Trilinear, iv::Blend::Paper);
    for (int set = 0; set < 2; ++set) {
        double numLin = 0, numCub = 0, numPaper = 0, den = 0, refVar = 0, signedLin = 0, signedPaper = 0, sumRef = 0;
        int used = 0;
        for (int i = set * count; i < (set + 1) * count; ++i) {
            const double r = luminance(Rgb(ref[i].irradiance));
            if (!(r > 1e-6)) continue;  // inside a solid block: no light reaches it
            const Vec3f n = normalize(points[i].normal);
            const double a = luminance(lin.irradiance(points[i].position, n));
            const double b = luminance(cub.irradiance(points[i].position, n));
            const double p = luminance(paper.irradiance(points[i].position, n));
            numLin += (a - r) * (a - r), numCub += (b - r) * (b - r), numPaper += (p - r) * (p - r), den += r * r;
            signedLin += a - r, signedPaper += p - r, sumRef += r;
            const double se = luminance(Rgb(ref[i].standardError));
            refVar += se * se;
            ++used;
        }
        const double errLin = std::sqrt(numLin / den), errCub = std::sqrt(numCub / den), errPaper = std::sqrt(numPaper / den);
        const double biasLin = signedLin / sumRef, biasPaper = signedPaper / sumRef;
        std::printf("default scene, %dx%dx%d grid, 2 M photons, %d free-space points, %s normals: relative RMS error vs "
                    "reference %.4f trilinear, %.4f tricubic, bias %+.4f (reference noise alone %.4f); paper blend RMS "
                    "%.4f, bias %+.4f\n",
                    g.nx, g.ny, g.nz, used, set ? "axis" : "random", errLin, errCub, biasLin, std::sqrt(refVar / den), errPaper,
                    biasPaper);
        ASSERT_GE(used, 1000);
        // Measured: random normals 0.160 trilinear / 0.131 tricubic, bias -0.007 (the paper's
        // blend: 0.272, bias -0.249); axis normals 0.161 / 0.125, bias -0.019.
        const double bound = set ? 0.22 : 0.20;
        EXPECT_LT(errLin, bound);
        EXPECT_LT(std::abs(biasLin), 0.03);
        EXPECT_LT(errCub, bound);
    }
}
