// What a probe stage volume carries forward for the probe pass's levers (issue 32: the
// default's guided directions and pass-0 blend in a tiled bake). (Internal to the bake module.)
//
// A staged bake (tiles.h) runs pass 0 in stage 0 and the probe pass in stage 1, in separate
// processes. The probe pass's guide (direction_guide.h) and the blend with pass 0
// (volume/first_pass_blend.h) read what pass 0 found at every node: its luminance per direction
// cell, its values and its error. So a stage-0 volume of a bake with either lever holds, per
// node, after the nine reflected-light channels (probeStageBasis):
// - with the blend, pass 0's stored values (`first_pass_<i>`, one channel per channel of the
//   stored basis);
// - with either, `first_pass_error`: pass 0's relative standard error, and 1 where pass 0 found
//   the node inside a solid (a guided probe pass does not classify: pass 0's stays);
// - with the guide, its luminance sums and sample counts per direction cell, 2 x kCells floats
//   packed into channels `guide_<i>` (counts are integers below 2^24: exact as floats).
// Full floats (a stage file is never half float), so stage 1 reads pass 0's exact bits and the
// merged tiles equal the single bake.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "vdblight/basis/basis.h"
#include "vdblight/volume/volume.h"

namespace vdblight::bake_detail {

struct StageCarry {
    std::size_t firstPassFloats = 0;  ///< pass 0's stored values per node (the blend); 0: none
    bool guide = false;               ///< pass 0's guide sums and counts

    static constexpr std::size_t kReflectedFloats = 27;  ///< the nine reflected-light channels
    bool any() const { return firstPassFloats > 0 || guide; }
    std::size_t firstValuesAt() const { return kReflectedFloats; }
    std::size_t errorAt() const { return firstValuesAt() + firstPassFloats; }  ///< error, inside solid, 0
    std::size_t guideAt() const { return errorAt() + (any() ? 3 : 0); }          ///< sums, then counts
    std::size_t floatsPerNode() const;
    /// probeStageBasis() with the channels above.
    BasisDesc basis() const;
    /// What a stage volume of basis `b` carries (its channel names; FormatError if they are not
    /// a carry's).
    static StageCarry of(const BasisDesc& b);
};

/// Lays `stage` (a stageVolume, nine reflected channels per held node) out as `carry`
/// says, with pass 0's values (`firstValues`, carry.firstPassFloats per held node), errors,
/// inside-solid flags (empty: none) and guide sums and counts (DirectionGuide::kCells per held
/// node), each as the bake holds them (held-node order).
void carryIntoStage(Volume& stage, const StageCarry& carry, const std::vector<float>& firstValues,
                    const std::vector<float>& firstError, const std::vector<uint8_t>& insideSolid,
                    const std::vector<float>& guideSums, const std::vector<uint32_t>& guideCounts);

/// Held node h of a tile's window [windowFirst, windowFirst + held) reads node windowFirst + h of
/// the stage input (every node, StageCarry layout): pass 0's values, errors and inside-solid
/// flags of the window. Vectors the caller does not need may be null.
void readCarriedFirstPass(const Volume& stageInput, const StageCarry& carry, std::size_t windowFirst, std::size_t held,
                          std::vector<float>* firstValues, std::vector<float>* firstError,
                          std::vector<uint8_t>* insideSolid);

/// How far in node order a node's neighbours within `radius` steps lie (radius x (1 + nx + nx ny)):
/// a tile of stage 1 reads the stage input from its window's first node minus this to its
/// last plus this (bake_volume.cpp), not every node.
std::size_t stageReach(const GridSpec& grid, int radius);

/// The window's guide sums and counts pooled over `radius` (poolGuideSums) from the stage
/// input's (every node, or a window of it covering stageReach around the tile's): the same
/// additions, in the same order, as the single bake's pooling.
void poolCarriedGuide(const Volume& stageInput, const StageCarry& carry, const GridSpec& grid, int radius, int threads,
                      std::size_t windowFirst, std::size_t held, std::vector<float>& sums, std::vector<uint32_t>& counts);

}  // namespace vdblight::bake_detail
