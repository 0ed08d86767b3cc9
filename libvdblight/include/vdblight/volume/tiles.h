// The volume module's tiles of a bake, in two parts: the photon pass's exact sums (below) and
// the tiles, their files and their merge (second part).
//
// Exact photon sums (issue 17, tiles of the photon pass; bake/each_pass.h, volume/tiles.h).
//
// The photon pass adds each batch of photons into a float buffer, then every batch's buffer
// into the total. The total is kept as 128-bit fixed-point integers: each batch's float sum
// is rounded once to a multiple of one quantum q, and integers add exactly in any order and
// grouping. So the single bake (every batch) and the merge of photon tiles (each tile the
// sum of a run of batches) hold the same integers, and give the same floats, byte for byte.
// (A double total added in batch order, as before, depends on the grouping: tile partial sums
// added at the merge would round differently.)
//
// Scale: q = 2^exponent with exponent = ilogb(Phi) - 80, Phi the largest colour component of
// the scene's emitted power (PhotonEmitter::totalPower): the same for every tile of a bake,
// and in the units of the sums (a photon carries its light's share of Phi / photons).
//
// Range (nothing can overflow): a batch's sum of one value must satisfy
// |sum| <= 2^(exponent + 118) = 2^(ilogb(Phi) + 38) >= 2^37 Phi (checked; a bake beyond it
// stops with ValueError rather than wrap). A bake has at most 256 batches (photonBatchSize),
// so every total, a bake's or a merge's, is below 256 * 2^118 = 2^126 quanta < 2^127. Real
// sums are the flux through one dual face: at most a few times Phi (light crossing the face
// again after bounces; 1 / (1 - albedo) in a white furnace), times the flux estimator's
// 1 / |w_a| for grazing photons; 2^37 Phi is 11 orders of magnitude above that.
//
// Precision: q <= 2^-80 Phi; rounding each batch loses at most q / 2, so a total is within
// 128 q <= 2^-73 Phi of the exact sum of the batches' floats. Relative to the largest value a
// total may hold (2^126 q) that is 2^-126; every sum of at least 2^-49 Phi keeps float's full
// 24-bit precision (its error is at most half a float ulp of it). The stored value is
// float(double(total) * q / area), the same rounding as before for any total below 2^53 q.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "vdblight/layout/layout.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/volume/volume.h"

#if !defined(__SIZEOF_INT128__)
#error "vdblight's photon sums need a 128-bit integer type (GCC and Clang on 64-bit targets)"
#endif

namespace vdblight {

/// One fixed-point photon sum: an integer count of quanta 2^PhotonSums::exponent.
using PhotonFixed = __int128;

/// Where the photon sums of direction d at node (i, j, k) are: direction-major, and within a
/// direction the axis of that direction varies fastest, so that the crossings of one segment
/// with the planes normal to axis a are neighbours in memory (a stride of 9 values), which
/// keeps the photon walk in cache. 9 values (colour-major vectors) per (direction, node).
struct PhotonSumLayout {
    std::size_t nodes = 0;
    std::size_t stride[3][3];  ///< stride[a][b]: step in nodes of index b in the arrays of axis a

    explicit PhotonSumLayout(const GridSpec& g) : nodes(g.nodeCount()) {
        const std::size_t n[3] = {std::size_t(g.nx), std::size_t(g.ny), std::size_t(g.nz)};
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            stride[a][a] = 1;
            stride[a][b] = n[a];
            stride[a][c] = n[a] * n[b];
        }
    }
    /// First value of (direction d, node (i, j, k)); 9 values (colour-major vectors) follow.
    std::size_t offset(int d, int i, int j, int k) const {
        const int a = d / 2;
        return (std::size_t(d) * nodes + i * stride[a][0] + j * stride[a][1] + k * stride[a][2]) * 9;
    }
};

/// The photon pass's sums over some of its batches (all of them: a bake; a run: a tile).
struct PhotonSums {
    GridSpec grid;                    ///< the pass's nodes (placed as the volume is)
    int exponent = 0;                 ///< a value is integer * 2^exponent (photonSumExponent)
    std::vector<PhotonFixed> values;  ///< PhotonSumLayout order, iv::kFloatsPerNode per node
    /// The batches summed: [firstBatch, endBatch) of the bake's `batches`.
    uint64_t firstBatch = 0, endBatch = 0, batches = 0;
    bool complete() const { return firstBatch == 0 && endBatch == batches; }
};

/// The quantum's exponent for emitted power `maxPower` (the largest colour component of the
/// scene's total, > 0 and finite; ValueError otherwise): ilogb(maxPower) - 80.
int photonSumExponent(double maxPower);

/// A batch's float sum in quanta 2^exponent (rounded to nearest, ties away from zero), or
/// false if it is not finite or exceeds the per-batch range 2^118 quanta (header comment).
/// `scale` = 2^-exponent (exact: a power of two; the product is exact in double).
inline bool toPhotonFixed(float v, double scale, PhotonFixed& out) {
    const double d = double(v) * scale;
    if (!(std::abs(d) <= 0x1p118)) return false;  // NaN fails too
    if (std::abs(d) >= 0x1p62) {
        // An integer already (>= 2^53): mantissa << exponent, exact (and faster than the
        // compiler's double -> 128-bit conversion, a library call).
        uint64_t bits;
        std::memcpy(&bits, &d, sizeof bits);
        const int shift = int((bits >> 52) & 0x7ff) - 1075;  // >= 10 here
        const PhotonFixed magnitude = PhotonFixed((bits & 0xfffffffffffffull) | (1ull << 52)) << shift;
        out = (bits >> 63) ? -magnitude : magnitude;
        return true;
    }
    const int64_t t = int64_t(d);       // truncated; d - t is exact (the fraction of d)
    const double frac = d - double(t);
    out = PhotonFixed(t + (frac >= 0.5 ? 1 : 0) - (frac <= -0.5 ? 1 : 0));
    return true;
}

/// The batches of tile `index` of `count` of a photon bake with `batches` batches: the
/// contiguous run [first, end) = [index * batches / count, (index + 1) * batches / count).
/// ValueError unless 1 <= count <= batches and 0 <= index < count.
void photonTileBatches(uint64_t batches, int count, int index, uint64_t& first, uint64_t& end);

/// The irradiance-vector volume of complete sums (every batch; ValueError otherwise): each sum divided by its node's
/// dual-face area (h^2, halved on the node box's boundary) into node-major order, basis
/// iv::basis(), metadata `meta`. The single bake and the merge of photon tiles both call it.
Volume photonVolume(const PhotonSums& sums, Metadata meta);

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// Tiles: one bake split over several processes or machines, merged exactly (issue 17;
// docs/format.md "Tiles", docs/scaling.md).
//
// The nodes of every level are cut into bricks of 8^3 nodes (the VDB leaf nodes of the
// level's grids); the bricks, in the order (level, z, y, x), are cut into `count` contiguous
// runs of about equal estimated cost. Tile i bakes only the nodes of its bricks and writes a
// partial .vdb that records its identity and a hash of the scene and every bake parameter.
// mergeTiles puts the tiles back together, applies what crosses tile borders (seam
// constraints of bilevel / adaptive layouts, the point gather's node filter) and gives exactly the volume a single-process
// bake gives, so that writing it gives the same bytes.
//
// The photon pass is tiled by photon batches instead (its photons cross every node): tile i
// traces a run of the batches and writes the whole grid's exact sums of them
// (writePhotonTile, volume/tiles.h); the merge adds the tiles' sums. Depth moments, which are
// per node (bake/each_pass.h), are split by node instead: tile i bakes those of a contiguous run of
// the nodes (photonTileDepthNodes) and the merge puts the runs together.

namespace vdblight {

/// Per level, one flag per stored node (its position in VolumeLevel::data): 1 = in the set.
using NodeMask = std::vector<std::vector<uint8_t>>;

/// What a tile file says about itself.
struct TileId {
    int index = 0;
    int count = 1;
    /// SHA-256 of the scene's content hash and every bake parameter: equal for the tiles of
    /// one bake, different for anything that would change the merged file.
    std::string paramsHash;
};

/// The hash TileId::paramsHash holds: of the scene content hash and a canonical text of every
/// bake parameter (one "name=value" per line; the caller leaves out the tile index, output
/// path, thread count and other options that do not change the result).
std::string tileParamsHash(const std::string& sceneHash, const std::string& parameters);

/// Bricks of 8^3 nodes over all levels of `levels` (structure only: grid and activeNodes).
uint64_t countBricks(const std::vector<VolumeLevel>& levels);

/// The nodes of tile `index` of `count` (see above; the estimated cost of a brick is its
/// number of nodes). Throws ValueError unless 1 <= count <= countBricks(levels) and
/// 0 <= index < count.
NodeMask tileNodeMask(const std::vector<VolumeLevel>& levels, int count, int index);

/// Tile-local memory: sets every level's window (VolumeLevel::windowFirst, windowNodes) to the
/// stored positions from the first to the last node of `only` in that level (a level without
/// any: the first position only, so that every level keeps its arrays), or to every position
/// without `only`. A tile's bricks are a contiguous run in (level, z, y, x) order, so its
/// window spans its own nodes plus at most the partial rows of bricks at both ends.
void setTileWindows(std::vector<VolumeLevel>& levels, const NodeMask* only);

/// Per-node statistics a tile carries so that the merge can summarise them over the whole
/// volume (they are not stored in complete volumes).
struct TileNodeStats {
    /// Single-level volumes: per node of level 0's window (node order; VolumeLevel::heldNodes), the estimated relative standard
    /// error of the point gathers (BakeStats::estimatedError); the merge recomputes the error
    /// summary (volume/volume.h) from it. Empty: none.
    std::vector<float> estimatedError;
    /// A last-stage tile of a bake that blends pass 0 in (BakeStats::firstPassValues): pass 0's
    /// values (the basis's floats per node) and errors over the same window; the merge blends
    /// them in after putting the nodes together, as the single bake does. Empty: none.
    std::vector<float> firstPassValues, firstPassError;
};

/// Writes the nodes of `volume` in `mask` as tile `id` (partial .vdb, atomically as
/// writeVolume; the header UUID is derived from the content): their basis channels, depth
/// moments and light visibility, the light list, and `stats` of the tile's nodes. Values are
/// stored as full floats even with options.halfFloat, which is recorded for the merged file.
/// Refuses volumes with validity.
void writeTile(const Volume& volume, const NodeMask& mask, const TileId& id, const std::string& path,
               const WriteOptions& options = {}, const TileNodeStats* stats = nullptr);

/// The nodes whose depth moments tile `index` of `count` of a photon bake bakes (bake
/// --depth-moments): linear indices [index * n / count, (index + 1) * n / count) of the n nodes
/// of `grid`, as a one-level mask. Any count works (a run may be empty: more tiles than nodes);
/// a node's moments do not depend on the run it is baked in (bake/each_pass.h), so the merged
/// runs are the single bake's. ValueError unless 1 <= count and 0 <= index < count.
NodeMask photonTileDepthNodes(const GridSpec& grid, int count, int index);

/// Writes tile `id` of a photon bake (bake/each_pass.h, volume/tiles.h; partial .vdb, atomically as
/// writeVolume): the whole grid's exact sums of the tile's batches (two Int64Grids per value,
/// tile_photon_sum_<v>_hi / _lo, v = 0..53 the volume's float order), `meta` (the volume's
/// metadata; the counts of the tile's batches) and tile_* keys; `compact`: the merge writes
/// the compact form (bake --compact). `depth` (bake --depth-moments; else null): the depth
/// moments of the tile's nodes (photonTileDepthNodes), as a level on the sums' grid whose
/// activeNodes list them (ascending linear indices, maybe none) and whose `depth` holds their
/// moments in that order; written as the four depth grids active exactly there (tile_depth 1).
/// Refuses sums that do not match their grid, depth that does not match its nodes.
void writePhotonTile(const PhotonSums& sums, const Metadata& meta, const TileId& id, const std::string& path,
                     const WriteOptions& options, bool compact, const VolumeLevel* depth = nullptr);

/// Reads the identity of a tile file. Returns false for a .vdb that is no tile (a complete
/// volume); throws as readVolume for unreadable files.
bool readTileId(const std::string& path, TileId& id);

/// What `vdblight info` lists of a tile file: its identity, size, content hash and grids;
/// tileInfoJson: identity, size and content hash as JSON.
std::string tileInfoText(const TileId& id, const FileInfo& info);
std::string tileInfoJson(const TileId& id, const FileInfo& info);

/// The merged volume and how to write it (the tiles' half-float and reproducible settings).
struct MergedTiles {
    Volume volume;
    WriteOptions write;
};

/// Merges the tile files of one bake. Throws ValueError naming the files for a missing,
/// duplicate or mismatched tile (other tile count or parameter hash), FormatError for files
/// that are no tiles or overlap. Photon tiles (writePhotonTile): their exact sums are added
/// and normalised by photonVolume, as the single bake does; their depth moments, if any, put
/// together (FormatError if some tiles have them and others not, or if a node's are held by
/// two tiles or by none). Counts each tile measured for its own nodes
/// (tileSummedKeys) are summed in tile order; the error summary is recomputed from the
/// tiles' per-node errors, the sample summary of error-targeted bakes from the summed counts.
MergedTiles mergeTiles(const std::vector<std::string>& paths);

/// Metadata counts (rays, samples, ...) that a tile measures for its own nodes and the merge
/// sums in tile order.
const std::vector<std::string>& tileSummedKeys();

// ---------------------------------------------------------------------------------------
// Staged bakes: passes that read every node of the pass before (the probe-to-probe passes,
// GatherOptions::probePasses) are tiled one pass at a time. Stage s (0..passes) bakes pass s
// of the tile's nodes; a stage before the last writes a probe stage volume (the pass's
// reflected light per node, probeStageBasis, plus what later stages carry forward: depth
// moments, counts); its tiles merge into one complete stage file, which every tile of
// stage s + 1 reads (readProbeStage). The tiles of the last stage merge into the volume a
// single-process bake gives. docs/scaling.md, "Staged bakes".

/// The basis of a probe stage volume: nine RGB SH order-2 radiance coefficients per node of
/// the pass's reflected light and sky (kind "sh2_reflected", channels reflected_sh_0..8).
BasisDesc probeStageBasis();

/// For a tile of stage s > 0: records the stage input's summed counts (tileSummedKeys) as
/// tile_earlier_<key>, which the merge adds once, so the merged counts cover every stage.
void addEarlierStageSums(Metadata& tileMeta, const Metadata& stageInput);

/// Reads a merged probe stage file (written by mergeTiles + writeVolume from stage tiles;
/// vdblight:probe_stage set). Throws FormatError for any other file. readVolume refuses
/// stage files: they hold reflected light, not a volume to look up. `knownHash`: the file's
/// content hash if the caller has computed it (a stage tile hashes its input for its parameter
/// hash), so the check for damaged files does not hash the file again. `window` (count > 0):
/// only those nodes of the stage (VolumeLevel::windowFirst), for a tile that reads no more.
struct NodeWindow {
    std::size_t first = 0, count = 0;
};
Volume readProbeStage(const std::string& path, const ContentHash* knownHash = nullptr, NodeWindow window = {});

// ---------------------------------------------------------------------------------------
// A tiled bake as Slurm jobs (`vdblight slurm`, docs/scaling.md): per stage a job array of
// tiles and a merge job after it (afterok), each stage's array after the merge before.

struct SlurmJobs {
    std::string program;  ///< the vdblight executable the jobs run
    std::string scene;    ///< the scene file
    std::string output;   ///< the merged .vdb; scripts and tiles go to OUTPUT.tiles/
    int tiles = 1;        ///< array tasks per stage
    int stages = 1;       ///< the bake's probe passes + 1 (tiledBakeStages, bake_volume.h)
    std::vector<std::string> bakeArgs;  ///< the bake options of every tile, as given
    std::string sbatch;   ///< extra sbatch options for every job ("--partition=bake --cpus-per-task=8")
};

/// Writes OUTPUT.tiles/: tiles[-S].sbatch and merge[-S].sbatch per stage S, submit.sh (submits
/// them in order and records the job ids in `jobs`) and `tiles` (tile and stage counts), each
/// atomically. Returns the directory.
std::string writeSlurmJobs(const SlurmJobs& jobs);

/// What OUTPUT.tiles/ holds (`vdblight slurm --status`): the counts writeSlurmJobs recorded,
/// the tiles of each stage on disk, the job ids submit.sh recorded (tiles, merge, per stage).
struct SlurmJobsState {
    std::string directory;
    int tiles = 0, stages = 1;
    std::vector<int> tilesOnDisk;
    std::vector<std::string> jobIds;
};
/// IoError if `output` has no tiled bake (no OUTPUT.tiles/tiles).
SlurmJobsState readSlurmJobs(const std::string& output);

/// `text` single-quoted for sh.
std::string shellQuote(const std::string& text);

}  // namespace vdblight
