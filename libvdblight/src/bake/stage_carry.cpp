// What a probe stage volume carries forward for the probe pass's levers (stage_carry.h).

#include "bake/stage_carry.h"

#include <algorithm>
#include <string>

#include "bake/direction_guide.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/tiles.h"

namespace vdblight::bake_detail {

namespace {
constexpr std::size_t kGuideFloats = 2 * DirectionGuide::kCells;  // sums, then counts
constexpr std::size_t kGuideChannels = (kGuideFloats + 2) / 3;
const std::string kFirstPass = "first_pass_", kError = "first_pass_error", kGuide = "guide_";

bool startsWith(const std::string& s, const std::string& prefix) { return s.compare(0, prefix.size(), prefix) == 0; }
}  // namespace

std::size_t StageCarry::floatsPerNode() const { return guideAt() + (guide ? kGuideChannels * 3 : 0); }

BasisDesc StageCarry::basis() const {
    BasisDesc b = probeStageBasis();
    for (std::size_t c = 0; c < firstPassFloats / 3; ++c) b.channelNames.push_back(kFirstPass + std::to_string(c));
    if (any()) b.channelNames.push_back(kError);
    for (std::size_t c = 0; guide && c < kGuideChannels; ++c) b.channelNames.push_back(kGuide + std::to_string(c));
    return b;
}

StageCarry StageCarry::of(const BasisDesc& b) {
    // Read what the names say is carried, then require exactly the names that carry has.
    StageCarry carry;
    for (const std::string& name : b.channelNames) {
        if (startsWith(name, kFirstPass) && name != kError) carry.firstPassFloats += 3;
        carry.guide = carry.guide || startsWith(name, kGuide);
    }
    if (carry.basis().channelNames != b.channelNames)
        throw FormatError("a probe stage volume's channels are not what a stage carries (stage_carry.h)");
    return carry;
}

std::size_t stageReach(const GridSpec& grid, int radius) {
    return std::size_t(std::max(radius, 0)) * (1 + std::size_t(grid.nx) + std::size_t(grid.nx) * std::size_t(grid.ny));
}

void carryIntoStage(Volume& stage, const StageCarry& carry, const std::vector<float>& firstValues,
                    const std::vector<float>& firstError, const std::vector<uint8_t>& insideSolid,
                    const std::vector<float>& guideSums, const std::vector<uint32_t>& guideCounts) {
    if (!carry.any()) return;
    constexpr std::size_t kCells = DirectionGuide::kCells;
    VolumeLevel& level = stage.levels.at(0);
    const std::size_t held = level.data.size() / StageCarry::kReflectedFloats, stride = carry.floatsPerNode();
    if (firstError.size() != held || (carry.firstPassFloats && firstValues.size() != held * carry.firstPassFloats) ||
        (carry.guide && (guideSums.size() != held * kCells || guideCounts.size() != held * kCells)) ||
        (!insideSolid.empty() && insideSolid.size() != held))
        throw ValueError("what a stage carries does not match its nodes");
    std::vector<float> data(held * stride, 0.0f);
    for (std::size_t h = 0; h < held; ++h) {
        float* out = data.data() + h * stride;
        std::copy_n(level.data.data() + h * StageCarry::kReflectedFloats, StageCarry::kReflectedFloats, out);
        std::copy_n(firstValues.data() + h * carry.firstPassFloats, carry.firstPassFloats, out + carry.firstValuesAt());
        out[carry.errorAt()] = firstError[h];
        out[carry.errorAt() + 1] = !insideSolid.empty() && insideSolid[h] ? 1.0f : 0.0f;
        if (!carry.guide) continue;
        float* guide = out + carry.guideAt();
        std::copy_n(guideSums.data() + h * kCells, kCells, guide);
        for (std::size_t cell = 0; cell < kCells; ++cell) {
            if (guideCounts[h * kCells + cell] >= (1u << 24)) throw ValueError("a guide cell's count is beyond a float's integers");
            guide[kCells + cell] = float(guideCounts[h * kCells + cell]);
        }
    }
    level.data.swap(data);
    stage.basis = carry.basis();
}

void readCarriedFirstPass(const Volume& stageInput, const StageCarry& carry, std::size_t windowFirst, std::size_t held,
                          std::vector<float>* firstValues, std::vector<float>* firstError,
                          std::vector<uint8_t>* insideSolid) {
    const std::size_t stride = carry.floatsPerNode();
    const VolumeLevel& stage = stageInput.levels.at(0);  // maybe a window of it (readProbeStage)
    if (!carry.any() || windowFirst < stage.windowFirst || stage.held(windowFirst) + held > stage.heldNodes() ||
        stage.data.size() != stage.heldNodes() * stride)
        throw ValueError("the stage input does not carry pass 0 for these nodes");
    if (firstValues) firstValues->resize(held * carry.firstPassFloats);
    if (firstError) firstError->resize(held);
    if (insideSolid) insideSolid->resize(held);
    for (std::size_t h = 0; h < held; ++h) {
        const float* node = stage.data.data() + stage.held(windowFirst + h) * stride;
        if (firstValues)
            std::copy_n(node + carry.firstValuesAt(), carry.firstPassFloats, firstValues->data() + h * carry.firstPassFloats);
        if (firstError) (*firstError)[h] = node[carry.errorAt()];
        if (insideSolid) (*insideSolid)[h] = node[carry.errorAt() + 1] != 0.0f ? 1 : 0;
    }
}

void poolCarriedGuide(const Volume& stageInput, const StageCarry& carry, const GridSpec& grid, int radius, int threads,
                      std::size_t windowFirst, std::size_t held, std::vector<float>& sums, std::vector<uint32_t>& counts) {
    constexpr std::size_t kCells = DirectionGuide::kCells;
    const std::size_t stride = carry.floatsPerNode();
    const VolumeLevel& stage = stageInput.levels.at(0);  // maybe a window of it (readProbeStage)
    const std::size_t reach = stageReach(grid, radius);
    const std::size_t from = windowFirst > reach ? windowFirst - reach : 0,
                      to = std::min(grid.nodeCount(), windowFirst + held + reach);
    if (!carry.guide || stage.data.size() != stage.heldNodes() * stride || windowFirst + held > grid.nodeCount() ||
        from < stage.windowFirst || to > stage.windowFirst + stage.heldNodes())
        throw ValueError("the stage input carries no guide for these nodes and their neighbours");
    const float* guide = stage.data.data() + carry.guideAt();
    sums.assign(held * kCells, 0.0f);
    counts.assign(held * kCells, 0);
    poolGuideWindow(
        grid, radius, windowFirst, held, threads, [&](std::size_t n) { return guide + stage.held(n) * stride; },
        [&](std::size_t n) { return guide + stage.held(n) * stride + kCells; }, sums.data(), counts.data());
}

}  // namespace vdblight::bake_detail
