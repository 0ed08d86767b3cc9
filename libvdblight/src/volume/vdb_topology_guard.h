// A grid's tree topology counts, checked against the bytes the grid has before OpenVDB reads
// its tree. Internal to the volume module (called by vdb_open.cpp's grid table scan).
//
// OpenVDB 10's RootNode::readTopology reads a tile count and a child count (32-bit each) and
// loops over them without checking its stream: a crafted tile count of 4 294 967 295 keeps
// io::Archive::readGrid reading an exhausted stream for minutes (fuzz_vdb's timeout,
// docs/measurements/robustness.md), and a crafted child count allocates a root child node
// (hundreds of kilobytes) per turn for as long as the stream lasts. Every tile takes a fixed
// number of bytes in the file and every child at least its two node masks, so a count the
// grid's bytes cannot hold is refused before OpenVDB starts looping.
#pragma once

#include <cstdint>
#include <istream>
#include <string>

namespace vdblight::vdb_detail {

/// One grid of a file, as its descriptor in the grid table gives it.
struct GridExtent {
    std::string name;      ///< its unique name
    std::string type;      ///< its grid type as stored (with "_HalfFloat" if saved as half floats)
    bool instance = false; ///< an instance shares another grid's tree and stores none of its own
    int64_t gridPos = 0;   ///< where its data starts (compression flags, metadata, transform, tree)
    int64_t endPos = 0;    ///< where its data ends (at most the file's size)
};

/// FormatError "'path' grid 'NAME' declares N root tiles (or child nodes), but ..." if the tree
/// of `grid` declares more root tiles or child nodes than the bytes between its topology and
/// its end can hold. Grids whose topology it cannot locate (a type or transform OpenVDB does
/// not know, a file format older than 213) are left to OpenVDB, whose read fails or works as
/// before. `is` is the file, tagged with its format version (io::Archive::setFormatVersion), and
/// each metadata length of the grid has been checked; its position is kept.
void checkTreeTopology(std::istream& is, const GridExtent& grid, const std::string& path);

}  // namespace vdblight::vdb_detail
