// The prt module's API: the transfer data and its bake (below), and its file (second part).
//
// Precomputed radiance transfer for moving local lights (Leonhardt & Bohn, "Precomputed
// Illumination for Virtual Reality Scenarios"); see docs/methods.md.
//
// Bake: surface samples spread uniformly over the scene (section 4.1), clustered; per-sample
// hemispherical depth buffers compressed by a per-cluster PCA (4.2); a per-cluster PCA basis
// of example direct lighting from point lights placed through the scene (4.3.1); transfer
// matrices from every sender cluster's basis vectors to every receiver sample (4.3.2, eq. 10)
// computed sample to sample with ray-traced visibility, for `bounces` diffuse bounces (the
// paper has one; more by iterating the form-factor matrix on the basis, multi_bounce.cpp).
// Relight (section 5): visibility -> direct light -> projection -> transfer -> indirect.
// The lights are the library's DirectLight (light/direct_light.h), the same description a volume
// lists; the method evaluates each as point emitters through the compressed visibility.
//
// Quantities: direct and indirect values are irradiance (W/m^2) at a sample on its front
// side; a sample's outgoing radiance is albedo / pi * (direct + indirect).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vdblight/light/direct_light.h"
#include "vdblight/layout/layout.h"
#include "vdblight/core/math.h"
#include "vdblight/volume/volume.h"

namespace vdblight {

struct Scene;
class Tracer;
class Interrupter;

/// A per-cluster PCA basis: an orthonormal basis of `count` row vectors of dimension `dim`
/// plus the mean row. Fitting and applying it are internal to the prt module (src/prt/pca.h).
struct PcaBasis {
    int dim = 0;
    int count = 0;
    std::vector<float> mean;     ///< dim values (eq. 7's mu)
    std::vector<float> vectors;  ///< count x dim, row-major; rows are orthonormal (B of eq. 8)
    std::vector<double> singularValues;  ///< all of them (min(n, dim)), largest first
};

struct PrtOptions {
    double sampleRadius = 0;       ///< Poisson-disk radius (scene units); 0: derived from `samples`
    uint32_t samples = 2000;       ///< target sample count when sampleRadius == 0
    uint32_t clusterSize = 1000;   ///< about this many samples per cluster
    uint32_t visDirs = 2048;       ///< hemisphere directions per depth buffer (rounded to g*g)
    uint32_t visCoeffs = 50;       ///< PCA coefficients kept per depth buffer
    uint32_t trainLights = 1000;   ///< example point lights for the direct-light basis
    uint32_t transferCoeffs = 10;  ///< direct-light basis vectors per cluster
    /// Direct-light basis as the paper's eq. 7 (centred, examples as they are). Default
    /// (false): every example scaled to unit length and no centring, since lighting vectors
    /// form a cone (a brighter light scales them); this halves the held-out error here.
    bool paperBasis = false;
    /// > 0: the nodes of a uniform SH volume with this many nodes along the longest axis
    /// (placeUniformGrid over the scene bounds) are receivers too (relightable volume).
    int volumeResolution = 0;
    /// Diffuse bounces in the transfer (1 = the paper's single bounce). The default matches
    /// the foundation bake's maxBounces, so a relit volume compares with a `bake`.
    int bounces = 8;
    /// Rescale every receiver's form factors (a sample's row of F, a node's row of the volume
    /// gather) so that they sum to the part of its hemisphere (sphere) that rays find covered
    /// by surfaces (sampleClosure / nodeClosure; scale capped at 4: corner samples need up to 4). Disks miss the near field
    /// at edges; without this a closed box's 8-bounce furnace reads 0.957 instead of 0.996.
    bool closureNormalise = true;
    /// Form factors (sample to sample, and node to sample for a volume):
    ///  - Dense: every pair with one visibility ray and the disk formula: n^2 / 2 rays and
    ///    n^2 floats during the bake (refused above 8 GB, i.e. about 44 k samples);
    ///  - Sampled: formFactorRays stratified rays per receiver, each hit assigned to the
    ///    sample standing for the hit point: n * formFactorRays rays and entries, so the
    ///    paper's 45 k samples bake in minutes (Monte Carlo noise instead of the disk error);
    ///  - Auto: Dense up to kDenseFormFactorLimit samples, Sampled above.
    enum class FormFactors { Auto, Dense, Sampled };
    static constexpr uint32_t kDenseFormFactorLimit = 8192;
    FormFactors formFactors = FormFactors::Auto;
    uint32_t formFactorRays = 256;  ///< rays per receiver for Sampled (rounded up to a square)
    /// One-sided example lights per isotropic one (trainingLights): cosine emitters facing
    /// away from their nearest surface. Their residuals after projection onto the point
    /// lights' basis give `orientedCoeffs` more basis vectors per cluster, so that the basis
    /// also spans the half-space cut-off of one-sided (area) lights while point lights project
    /// as before. 0 (or orientedCoeffs 0): point lights only (as the paper); ignored with
    /// paperBasis.
    float orientedTraining = 1.0f;
    uint32_t orientedCoeffs = 2;   ///< vectors appended from the one-sided examples (0..256)
    uint64_t seed = 1;
    int threads = 0;               ///< 0: all cores
};

/// Surface samples, ordered by cluster (cluster c holds [clusterBegin[c], clusterBegin[c+1])).
struct SurfaceSamples {
    std::vector<Vec3f> position;
    std::vector<Vec3f> normal;   ///< unit front-face normal
    std::vector<Rgb> albedo;
    std::vector<uint32_t> cluster;
    std::vector<float> area;             ///< surface area each sample stands for (Voronoi estimate)
    std::vector<uint32_t> clusterBegin;  ///< clusters + 1 entries
    std::vector<Vec3f> clusterRoot;      ///< root point of each cluster
    double radius = 0;                   ///< Poisson-disk radius used
    double areaPerSample = 0;            ///< total surface area / sample count
    std::size_t size() const { return position.size(); }
    std::size_t clusters() const { return clusterRoot.size(); }
};

/// Area-weighted random candidates (independent of the tessellation), thinned in candidate
/// order by Poisson-disk elimination: a candidate is dropped if an accepted sample facing the
/// same side lies within `radius`. radius == 0 derives it from `targetCount`. Each sample's
/// area is estimated from 32 uniform points per sample assigned to their nearest sample
/// (facing the same side): thinning leaves the edges of faces denser than their interiors.
/// Then farthest-point clustering (see clusterSamples). Throws ValueError on bad counts.
SurfaceSamples generateSurfaceSamples(const Scene& scene, double radius, uint32_t targetCount,
                                      uint32_t clusterSize, uint64_t seed);

/// Farthest-point roots (first = sample 0, then the sample farthest from all roots, ties to
/// the lower index), round(n / clusterSize) of them at least one; every sample joins its
/// nearest root. Returns the cluster of each point.
std::vector<uint32_t> clusterSamples(const std::vector<Vec3f>& points, uint32_t clusterSize,
                                     std::vector<Vec3f>* roots = nullptr);

/// The g x g hemisphere directions: cell centres of the unit square through the
/// Shirley-Chiu concentric map to the disk, lifted to the hemisphere with equal areas.
/// Local frame: +Z is the normal.
Vec3f visibilityDirection(int g, int index);

/// The (up to) four nearest depth-buffer directions of a local direction (z > 0) and their
/// bilinear weights in the concentric square (paper figure 2). Returns how many (4).
int visibilityNeighbours(int g, const Vec3f& localDir, int index[4], float weight[4]);

/// How relighting evaluates lights (relightPrt, relightVolume, prtDirectLight).
struct PrtRelightOptions {
    /// A polygon or mesh light is areaSamples^2 point emitters through the compressed
    /// visibility (pointEmitters in src/prt: a parallelogram's grid of cell centres, other
    /// shapes stratified over their area), each a cosine emitter of its share of the area.
    int areaSamples = 5;
    /// relightVolume with a scene: shadow rays per node and polygon light for the visibility
    /// channels (bakeLightVisibility, as `bake --direct occlusion`), and their seed.
    uint32_t visibilitySamples = 64;
    uint64_t seed = 1;
    int threads = 0;  ///< relightVolume's visibility channels (0: all cores)
};

/// The baked data (what a _prt.vdb holds).
struct PrtData {
    SurfaceSamples samples;
    int visGrid = 0;             ///< g: depth buffers have g*g directions
    float depthCap = 0;          ///< depth stored for rays that leave the scene
    std::vector<PcaBasis> visBasis;     ///< per cluster, dim = g*g
    /// Run-time copy of visBasis by direction (per cluster: [t * (count + 1)]: the mean, then
    /// the count basis values of direction t), so a depth lookup reads one contiguous row.
    /// Filled by prepareRelight (bakePrt and readPrt call it); empty: read visBasis.
    std::vector<std::vector<float>> visByDirection;
    std::vector<float> visCoeffs;       ///< per sample, visCoeffStride values (zero padded)
    int visCoeffStride = 0;
    std::vector<PcaBasis> lightBasis;   ///< per cluster, dim = cluster size
    int transferStride = 0;             ///< transferCoeffs + orientedCoeffs + 1 (row 0 = the mean)
    /// transfer[s][k * samples + r]: irradiance at receiver r per unit basis coefficient k of
    /// sender cluster s (k = 0: the mean vector), RGB (sender albedo included), summed over
    /// bounces 1..bounces.
    std::vector<std::vector<Rgb>> transfer;
    /// Relightable volume (empty volumeTransfer if none): volumeTransfer[s][(k * nodes + node)
    /// * 9 + j] is SH coefficient j of the radiance arriving at the node per unit coefficient k
    /// after 1..bounces diffuse reflections (the lights' direct light is added at relight).
    GridSpec volumeGrid;
    std::vector<std::vector<Rgb>> volumeTransfer;
    /// Run-time copy of volumeTransfer as 16-bit integers, one scale per column (cluster s,
    /// coefficient k: volumeTransferScale[s][k] * q = the value; error <= scale / 2): the
    /// relight streams the whole matrix once per light, so half the bytes is about half the
    /// time. Filled by prepareRelight; empty: volumeTransfer is read.
    std::vector<std::vector<int16_t>> volumeTransferQ;
    std::vector<std::vector<float>> volumeTransferScale;
    bool hasVolume() const { return !volumeTransfer.empty(); }
    Bounds bounds;               ///< of the scene, in its local frame
    /// World position of the scene's local frame (Scene::origin): samples, bounds, volume
    /// nodes and relit lights are local; prtLocal converts a world point.
    Vec3d origin{0, 0, 0};
    std::string sceneName, sceneHash;
    uint64_t seed = 1;
    uint32_t trainLights = 0;
    float orientedTraining = 0.0f;  ///< PrtOptions::orientedTraining of the bake
    int orientedCoeffs = 0;         ///< of the transferStride - 1 vectors, the last ones from one-sided examples
    bool paperBasis = false;
    int bounces = 1;             ///< diffuse bounces in transfer / volumeTransfer
    bool closureNormalise = false;  ///< form factors rescaled to the covered hemisphere
    uint32_t formFactorRays = 0;    ///< 0: dense pair form factors; else sampled with this many rays
    double secondsSamples = 0, secondsVisibility = 0, secondsBasis = 0, secondsTransfer = 0;
};

/// The whole bake. Throws ValueError on bad options (with a memory / ray estimate where a
/// count is absurd), Cancelled through `interrupter`.
PrtData bakePrt(const Scene& scene, const Tracer& tracer, const PrtOptions& options,
                Interrupter* interrupter = nullptr);

/// `count` example light positions: Halton points in the scene bounds (inset by 2%),
/// skipping points that classifyLightPosition calls inside a solid.
std::vector<Vec3f> trainingLightPositions(const Scene& scene, const Tracer& tracer, uint32_t count);

/// True if `p` looks inside a solid: most of six axis rays first hit a back face.
bool insideSolid(const Tracer& tracer, const Vec3f& p);

/// The same test from the PRT samples alone (no scene): at least 3/4 of the 8 samples nearest
/// to `p` face away from it. Used by `prt relight` to warn without the scene.
bool prtInsideSolid(const PrtData& prt, const Vec3f& p);

/// Fills prt.visByDirection (the run-time layout of the visibility bases).
void prepareRelight(PrtData& prt);

/// Per-sample relit irradiance (RGB, W/m^2).
struct PrtLighting {
    std::vector<Rgb> direct;
    std::vector<Rgb> indirect;
};

/// Direct irradiance per unit value of `light` (scalar: multiply by light.value) at every
/// sample through the compressed visibility: a point or spot light as one point emitter, a
/// polygon or mesh light as PrtRelightOptions::areaSamples^2 of them. Throws ValueError for a
/// directional light: the compressed visibility holds, per sample, the depth of the first hit
/// along its hemisphere directions, which answers whether a point at distance d is seen, and
/// the direct-light basis was trained with lights inside the scene; neither describes a light
/// at infinity. prtDirectUnit: an isotropic point of unit intensity at p.
std::vector<float> prtDirectLight(const PrtData& prt, const DirectLight& light, int areaSamples = 5);
std::vector<float> prtDirectUnit(const PrtData& prt, const Vec3f& p);

/// The reference for prtDirectLight, uncompressed and exact: exactIrradiance per unit value
/// times the shadowed fraction by rays (shadowedIrradiance of light/light.h, the light as a
/// freeLight: `samples` stratified points of a polygon, one ray to a point light), at every
/// sample. `scene` is the one `tracer` was built from. exactDirectUnit: an isotropic point of
/// unit intensity at p.
std::vector<float> exactDirectLight(const SurfaceSamples& s, const Scene& scene, const Tracer& tracer,
                                    const DirectLight& light, int threads = 0, uint32_t samples = 256);
std::vector<float> exactDirectUnit(const SurfaceSamples& s, const Scene& scene, const Tracer& tracer, const Vec3f& p,
                                   int threads = 0);

/// Section 5: direct from the compressed visibility, then projection onto each cluster's
/// basis and the transfer matrices. Lights add linearly (lights of one colour share one
/// projection and transfer). Positions in the PRT data's local frame (prtLocal).
PrtLighting relightPrt(const PrtData& prt, const std::vector<DirectLight>& lights, const PrtRelightOptions& options = {});

/// Indirect irradiance from a given per-sample direct unit irradiance `direct` (scalar),
/// through projection and transfer (eq. 10) only.
std::vector<Rgb> prtTransfer(const PrtData& prt, const std::vector<float>& direct);

/// SH radiance coefficients (9 per node, node-major) of the light reflected once by the
/// samples into the volume's nodes, for a given per-sample direct unit irradiance.
std::vector<Rgb> prtVolumeTransfer(const PrtData& prt, const std::vector<float>& direct);

/// A world point (double) in the PRT data's local frame, e.g. a light position given by a
/// user for a scene far from the origin (scene_origin.h).
inline Vec3f prtLocal(const PrtData& prt, const Vec3d& world) { return Vec3f(world - prt.origin); }

/// Relights the volume: an `sh2` Volume (one dense level) whose SH holds the radiance that
/// reaches each node after 1..prt.bounces diffuse reflections off the surfaces. With the baked
/// scene and its tracer (both or neither) it is a `--direct occlusion` volume like a bake's
/// (light/direct_light.h): Volume::direct lists the lights and level 0 holds their visibility
/// channels (bakeLightVisibility of bake/each_pass.h with the lights as freeLights), so `query`
/// and `export` add each light's exact irradiance times its interpolated visibility, as for a
/// baked occlusion volume. Without them it holds the reflected light only (metadata
/// `direct_light` = false). Placed in the world: its grid origin (and the listed lights) are
/// moved by prt.origin (placeVolumeInWorld). Throws ValueError if the PRT data has no volume.
Volume relightVolume(const PrtData& prt, const std::vector<DirectLight>& lights, const Scene* scene = nullptr,
                     const Tracer* tracer = nullptr, const PrtRelightOptions& options = {});

// --- References (uncompressed, for tests and error reports) ------------------------------

/// Uncompressed one-bounce indirect irradiance: every sample j reflects albedo_j / pi *
/// direct_j towards every receiver through the form factor below, visibility by ray
/// (pairVisible: one canonical ray per pair).
std::vector<Rgb> referenceIndirect(const SurfaceSamples& s, const Tracer& tracer, const std::vector<float>& direct,
                                   int threads = 0);

/// True if samples a and b see each other: one ray, from the lower index to the higher.
bool pairVisible(const SurfaceSamples& s, const Tracer& tracer, std::size_t a, std::size_t b);

/// The n x n form-factor matrix (row-major): F[r * n + j] = diskTransfer from sender j to
/// receiver r if pairVisible, else 0. n^2 / 2 rays, n^2 floats. With `normalise`, each row is
/// scaled to sum to pi * sampleClosure of its receiver (PrtOptions::closureNormalise). Throws
/// ValueError if the matrix would take more than 8 GB (about 44 k samples).
std::vector<float> sampleFormFactors(const SurfaceSamples& s, const Tracer& tracer, int threads = 0,
                                     Interrupter* interrupter = nullptr, bool normalise = false);

/// Cosine-weighted fraction of the hemisphere of (p, n) whose rays hit the scene (256 fixed
/// equal-area directions); nodeClosure: uniform fraction of the sphere around x.
float sampleClosure(const Tracer& tracer, const Vec3f& p, const Vec3f& n);
float nodeClosure(const Tracer& tracer, const Vec3f& x);

/// Uncompressed multi-bounce indirect irradiance E_1 + ... + E_bounces with E_1 = F A direct,
/// E_b = F A E_(b-1), A = albedo / pi (double sums). If asked, `senderIrradiance` gets
/// direct + E_1 + ... + E_(bounces-1): what the samples reflect towards volume nodes.
std::vector<Rgb> bounceIndirect(const SurfaceSamples& s, const std::vector<float>& F, const std::vector<Rgb>& direct,
                                int bounces, std::vector<Rgb>* senderIrradiance = nullptr);

/// Irradiance at a receiver (p, n) from a sender disk of area `area` at (q, m) with unit
/// radiance, without visibility: cos_r cos_s area / (d^2 + area / pi) (exact on axis).
inline float diskTransfer(const Vec3f& p, const Vec3f& n, const Vec3f& q, const Vec3f& m, float area) {
    const Vec3f w = q - p;
    const float d2 = dot(w, w);
    if (d2 <= 0.0f) return 0.0f;
    const float inv = 1.0f / std::sqrt(d2);
    const float cr = dot(n, w) * inv;
    const float cs = -dot(m, w) * inv;
    if (cr <= 0.0f || cs <= 0.0f) return 0.0f;
    return cr * cs * area / (d2 + area * float(kInvPi));
}

/// Uncompressed one-bounce SH radiance at the nodes of `grid` (9 per node) from every
/// sample, visibility by ray: sender j adds albedo_j / pi * direct_j * Y(w) * solid angle.
std::vector<Rgb> referenceVolume(const SurfaceSamples& s, const GridSpec& grid, const Tracer& tracer,
                                 const std::vector<float>& direct, int threads = 0);

/// The same with an RGB sender irradiance (e.g. bounceIndirect's senderIrradiance, for the
/// multi-bounce volume): sender j adds albedo_j / pi * irradiance_j * Y(w) * solid angle.
std::vector<Rgb> referenceVolume(const SurfaceSamples& s, const GridSpec& grid, const Tracer& tracer,
                                 const std::vector<Rgb>& senderIrradiance, int threads = 0);

/// Solid angle of a sender disk of area `area` at (q, m) seen from p: cos_s * 2 pi (1 -
/// d / sqrt(d^2 + area / pi)) (exact on axis, area cos / d^2 far away), 0 from behind.
inline float diskSolidAngle(const Vec3f& p, const Vec3f& q, const Vec3f& m, float area) {
    const Vec3f w = q - p;
    const float d2 = dot(w, w);
    if (d2 <= 0.0f) return 0.0f;
    const float d = std::sqrt(d2);
    const float cs = -dot(m, w) / d;
    if (cs <= 0.0f) return 0.0f;
    return cs * float(2.0 * kPi) * (1.0f - d / std::sqrt(d2 + area * float(kInvPi)));
}

/// sqrt(sum |a - b|^2 / sum |b|^2) over RGB components.
double rmsRelativeError(const std::vector<Rgb>& a, const std::vector<Rgb>& b);

/// What `vdblight prt relight` prints: per sample its world position, normal, cluster and
/// direct, indirect (W/m^2) and outgoing radiance (W/(m^2 sr)), as CSV or ASCII PLY.
std::string prtLightingTable(const PrtData& prt, const PrtLighting& lit, bool ply);

/// A light of `prt relight` given as text: its lights (DirectLight) in world coordinates, which
/// the caller moves into the PRT file's local frame (prtLocal), and the position given.
struct PrtLightSpec {
    std::vector<DirectLight> lights;
    Vec3d world;
};
/// --light x,y,z[,r,g,b] (intensity W/sr, white without it): a point light, or with `areaSize`
/// > 0 an isotropic square of that side in the XZ plane, `areaSamples`^2 point lights at its
/// cell centres sharing the intensity. ValueError naming the option and the text.
PrtLightSpec parsePointLightSpec(const std::string& text, double areaSize, int areaSamples);
/// --area-light x,y,z,nx,ny,nz,size[,r,g,b]: a square emitting on the side of the normal, the
/// intensity along the normal (a polygon light: squareLight).
PrtLightSpec parseAreaLightSpec(const std::string& text);
/// "x,y,z is outside the scene bounds (...)" or "... is inside a solid (...)" for a light at
/// `world` where the basis was not trained, or "". `tracer`: the scene's for the exact
/// inside-a-solid test (null: judged from the samples, prtInsideSolid).
std::string prtLightWarning(const PrtData& prt, const Tracer* tracer, const Vec3d& world);

/// A relighting against its ground truth (`prt relight --reference`): exact direct light by
/// shadow rays, uncompressed bounces with the bake's form factors; RMS relative errors.
struct PrtReferenceErrors {
    double direct = 0, indirect = 0;
};
PrtReferenceErrors prtReferenceErrors(const PrtData& prt, const PrtLighting& lit, const std::vector<DirectLight>& lights,
                                      const Scene& scene, const Tracer& tracer, int threads = 0);

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// PRT files: the samples as an OpenVDB PointDataGrid and the bases and transfer matrices as
// float grids used as sparse matrices (docs/prt_format.md).

namespace vdblight {

struct PrtWriteOptions {
    bool quantize = true;        ///< 16-bit storage (half floats) for coefficients and matrices
    float sparseThreshold = 0;   ///< matrix entries with |v| <= threshold * max|row| are dropped
};

/// Writes atomically (temporary file + rename). Throws IoError / ValueError.
void writePrt(const PrtData& prt, const std::string& path, const PrtWriteOptions& options = {});

/// Reads a file written by writePrt. Throws IoError, or FormatError if it is not a PRT file
/// (e.g. an SH volume).
PrtData readPrt(const std::string& path);

/// True if the file's metadata says it is a PRT file (FormatError if it is no .vdb at all).
bool isPrtFile(const std::string& path);

struct PrtFileInfo {
    uint64_t fileBytes = 0;
    uint64_t samples = 0, clusters = 0;
    uint64_t values = 0;         ///< stored numbers (coefficients, bases, matrices)
    uint64_t droppedValues = 0;  ///< entries dropped as near zero (sparse storage)
    uint64_t bytesFloat32 = 0;   ///< what the values take as 32-bit floats, dense
    uint64_t bytesStored = 0;    ///< what they take as stored (16-bit if quantised, sparse)
};
PrtFileInfo inspectPrt(const std::string& path);

/// What `vdblight prt info` lists of a PRT file: scene, samples and clusters, visibility and
/// direct-light bases, transfer, relightable volume, values and bytes stored, bake times.
std::string prtInfoText(const std::string& path);

}  // namespace vdblight
