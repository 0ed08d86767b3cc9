// Tiles: one bake split over several processes or machines, merged exactly (issue 17;
// docs/format.md "Tiles", docs/scaling.md).
//
// The nodes of every level are cut into bricks of 8^3 nodes (the VDB leaf nodes of the
// level's grids); the bricks, in the order (level, z, y, x), are cut into `count` contiguous
// runs of about equal estimated cost. Tile i bakes only the nodes of its bricks and writes a
// partial .vdb that records its identity and a hash of the scene and every bake parameter.
// mergeTiles puts the tiles back together, applies what crosses tile borders (seam
// constraints of bilevel / adaptive layouts) and gives exactly the volume a single-process
// bake gives, so that writing it gives the same bytes.
//
// The photon pass is tiled by photon batches instead (its photons cross every node): tile i
// traces a run of the batches and writes the whole grid's exact sums of them
// (writePhotonTile, photon_sums.h); the merge adds the tiles' sums. Depth moments, which are
// per node (bake_depth.h), are split by node instead: tile i bakes those of a contiguous run of
// the nodes (photonTileDepthNodes) and the merge puts the runs together.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vdblight/photon_sums.h"
#include "vdblight/vdb_io.h"
#include "vdblight/volume.h"

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
    /// summary (error_summary.h) from it. Empty: none.
    std::vector<float> estimatedError;
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
/// a node's moments do not depend on the run it is baked in (bake_depth.h), so the merged
/// runs are the single bake's. ValueError unless 1 <= count and 0 <= index < count.
NodeMask photonTileDepthNodes(const GridSpec& grid, int count, int index);

/// Writes tile `id` of a photon bake (photons.h, photon_sums.h; partial .vdb, atomically as
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
/// hash), so the check for damaged files does not hash the file again.
Volume readProbeStage(const std::string& path, const ContentHash* knownHash = nullptr);

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
