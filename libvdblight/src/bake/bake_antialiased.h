// Anti-aliased sampling and the domain of interest (Kontkanen & Laine 2006), and the
// engines' back-face invalidation heuristic it is compared with.
//
// The anti-aliased pass estimates, for every node i and SH coefficient j, eq. 5/6:
//   c_ij = sum_s L(x_s, w_s) Y_j(w_s) b_i(x_s) / (p(w_s) sum_s b_i(x_s))
// with ray origins x_s spread uniformly over each cell and directions w_s uniform on the
// sphere (p = 1/(4 pi)), both from one 5-D Halton point set (bases 2, 3 for the direction,
// 5, 7, 11 for the position) randomly shifted per cell; b_i is the trilinear basis function
// of node i. Emissive triangles
// add one NEE sample per origin (MIS as in the point pass), punctual lights are evaluated
// exactly at every origin.
//
// With DomainMode::Interior only origins in the domain of interest (space from which no
// back-face is visible) count: each cell is classified with the paper's Algorithm 2, whose
// sampling rays double as classification rays (an origin whose own ray hits a back-face is
// rejected and the hit becomes a back-face point; earlier and later origins are tested by
// query rays towards every known back-face point). In cells where back-faces were seen, a
// fallback (DomainFallback) then screens the accepted origins (one ray each) and tests the
// suspects with a few more rays, towards points on the back-facing triangles found and in
// further directions, because a surface can hide the cell's few known back-face points
// from origins outside the domain.
//
// Node values are eq. 6 (NodeFit::Projection) or, as an option, a least-squares fit of the
// node values to the same samples (NodeFit::LeastSquares, node_least_squares.h).
//
// Every node gets a validity: the fraction of its basis-function weight (over its cells'
// candidate origins) that fell in the domain. Nodes with no accepted weight at all are
// filled by dilation (dilateUnfilledNodes) and keep validity 0.
//
// Determinism: a cell's samples depend only on (seed, cell index, sample number); cells are
// reduced into nodes in cell order, so the volume has the same bits for any thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "vdblight/bake/each_pass.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

enum class DomainMode {
    All,       ///< every origin in the cell counts (pure eq. 6 pre-filtering)
    Interior,  ///< only origins that see no back-face (K&L section 5, Algorithm 2)
};

/// How node values are computed from a node's weighted samples (docs/methods.md).
enum class NodeFit {
    Projection,    ///< eq. 6: weighted sum / weight sum per node (the paper)
    LeastSquares,  ///< least-squares fit over the accepted samples (node_least_squares.h)
};

/// The check after Algorithm 2 in cells where it found back-face points (docs/methods.md):
/// an accepted origin whose line to the cell's first back-face point passes through a solid
/// and out of it again, or meets nothing, is a suspect (one continuation ray per accepted
/// origin); each suspect shoots `trianglePoints` query rays towards points on the
/// back-facing triangles found so far and `probes` rays in further directions, and any
/// back-face hit rejects it. {0, 0} is the paper's Algorithm 2 alone (no continuation rays).
struct DomainFallback {
    uint32_t trianglePoints = 4;
    uint32_t probes = 4;
};

struct AntialiasedOptions {
    /// Candidate ray origins (one ray each) per cell. A grid has about as many cells as
    /// nodes, so this matches GatherOptions::raysPerNode at an equal ray budget.
    uint32_t raysPerCell = 256;
    uint64_t seed = 1;
    int threads = 0;  ///< 0 = all hardware threads
    DomainMode domain = DomainMode::Interior;
    DomainFallback fallback;  ///< DomainMode::Interior only
    /// Experimental (off by default; docs/methods.md): an accepted origin contributes to a
    /// corner node only if the segment from the origin to the node is unoccluded (one
    /// occlusion ray per corner), so that a node's support does not reach across a wall
    /// thinner than a cell. Nodes that then get no weight are filled by dilation.
    bool visibleSupport = false;
    NodeFit fit = NodeFit::Projection;
    /// NodeFit::LeastSquares only: weight of the pull towards the eq.-6 values, relative to
    /// the Gram row sum of a node with full support (node_least_squares.h).
    double tikhonov = 0.05;
    /// NodeFit::LeastSquares only: the CG stops at this relative residual per SH coefficient
    /// and channel (solveNodeLeastSquares). The node values carry Monte Carlo noise of a few
    /// per cent; 1e-6 moves them by far less (docs/methods.md) at a third of 1e-10's iterations.
    double fitTolerance = 1e-6;
    TransportOptions transport;
};

/// Bakes an SH order-2 radiance volume on `grid` by eq. 6, with the level's validity
/// filled. Throws ValueError for bad options, SceneError if no origin of any cell lies in
/// the domain of interest (every face seen from its back: normals look reversed), Cancelled
/// if interrupted.
Volume bakeShAntialiased(const Scene& scene, const Tracer& tracer, const GridSpec& grid,
                         const AntialiasedOptions& options, Interrupter* interrupter = nullptr,
                         BakeStats* stats = nullptr);

/// Number of cells of `grid` along each axis (max(n - 1, 1)) and in total.
void cellDims(const GridSpec& grid, int& cx, int& cy, int& cz);
std::size_t cellCount(const GridSpec& grid);

/// Point sampling with the engines' leak heuristic: after the point-gather pass, a node
/// whose gathered rays hit back-faces in more than `maxBackfaceFraction` of cases is
/// invalid (validity 0, valid nodes 1) and is filled by dilateUnfilledNodes from its valid
/// neighbours. The coefficients of valid nodes are bit-identical to bakeShGather's.
/// Throws ValueError unless 0 <= maxBackfaceFraction <= 1, SceneError if every node is invalid.
Volume bakeShGatherInvalidated(const Scene& scene, const Tracer& tracer, const GridSpec& grid,
                               const GatherOptions& options, double maxBackfaceFraction,
                               Interrupter* interrupter = nullptr, BakeStats* stats = nullptr);

/// Fills nodes with filled[n] == 0 from their neighbours, in rings: each pass gives every
/// unfilled node that has filled nodes among its 26 neighbours the average of their
/// coefficients, weighted by weight[n] (> 0 for filled nodes) times 1 / (squared index
/// distance); a node filled in a pass counts as filled from the next pass on, with the mean
/// weight of its donors. Jacobi-style passes in node order: deterministic. Returns the number
/// of passes. Throws SceneError if no node is filled. `filled` and `weight` are updated.
int dilateUnfilledNodes(VolumeLevel& level, int channels, std::vector<uint8_t>& filled, std::vector<double>& weight);

}  // namespace vdblight
