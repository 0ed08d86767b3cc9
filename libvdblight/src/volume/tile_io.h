// Reading tile files (tiles.h), shared by vdb_read.cpp and merge.cpp. Internal.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "vdblight/volume/tiles.h"

namespace vdblight {
namespace vdb_detail {

/// A tile file: its identity and a partial volume whose every level lists the tile's nodes
/// in activeNodes (possibly none), with the full volume's grids and refined cells.
struct TileFile {
    TileId id;
    Volume part;
    std::vector<uint8_t> denseLevels;  ///< per level: the complete volume stores it dense
    bool halfFloat = false;
    bool reproducible = true;
    bool depth = false;       ///< the volume has depth moments (in part's levels, tile nodes)
    bool visibility = false;  ///< level 0 has light visibility (part.levels[0], tile nodes)
    bool edges = false;       ///< and the lights' shadow edges (shadow_edges.h)
    bool error = false;       ///< estimatedError holds level 0's per-node errors
    std::vector<float> estimatedError;  ///< TileNodeStats, in the order of part.levels[0].activeNodes
    bool firstPass = false;  ///< pass 0's values and errors for the merge's blend (TileNodeStats)
    std::vector<float> firstPassValues, firstPassError;  ///< in the same order
    /// A photon tile (writePhotonTile): the sums of its batches; part has the grid (level 0)
    /// and metadata, and with `depth` the depth moments of its run of nodes (level 0's
    /// activeNodes and depth; photonTileDepthNodes).
    std::shared_ptr<PhotonSums> photon;
    bool photonCompact = false;  ///< the merged file is the compact form
};

/// Reads a tile file. Throws FormatError if it is not one (or is corrupt), IoError if unreadable.
TileFile readTileFile(const std::string& path);

}  // namespace vdb_detail
}  // namespace vdblight
