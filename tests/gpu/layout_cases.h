// The table of the GPU-driver check: one row per (volume, export layout) an engine can load,
// each naming the GLSL of docs/engine*.md it runs. A new layout is one more row here plus its
// GLSL block in the document (found by the function it declares).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "export_loader.h"
#include "vdblight/export/export.h"

namespace vdblight::gpu {

/// (sampler uniform, manifest texture name) pairs: which texture each sampler reads.
using Bindings = std::vector<std::pair<std::string, std::string>>;

struct LayoutCase {
    const char* name;        ///< printed with the worst point
    const char* volume;      ///< a file of the suite's bakes (gpu_export_test.cpp)
    const char* exportArgs;  ///< `vdblight export` options after -o DIR
    /// Declarations that find the doc's GLSL blocks to include, in this order (doc_blocks.h).
    std::vector<const char*> docDeclarations;
    /// GLSL before the doc blocks (#defines the doc documents, from the manifest), or nullptr.
    std::string (*before)(const Manifest&);
    /// GLSL after them: `vec3 vdblightCheck(vec3 x, vec3 n)`, calling the doc's function, and
    /// the uniforms the doc's function takes as arguments.
    const char* glue;
    Bindings (*bind)(const Manifest&);
    int shOrder = 0;  ///< compare with the query of bands 0..shOrder (sh_truncate.h); 0: as stored
    /// Rows of volumes with depth moments: the check also proves that the weights matter
    /// (the unweighted lookup differs at some of the points).
    bool depthWeighted = false;
    /// Extra uniforms from the manifest (e.g. the listed light of an occlusion volume).
    void (*setUniforms)(const Manifest&, const ComputeProgram&) = nullptr;
    /// sh1-16 / sh2-32 rows (8-bit textures): the shader is compared with the query of
    /// compactShRoundTrip(volume, *compactSh) (what the textures decode to; the usual
    /// tolerance), and that query with the query of bands 0..shOrder within `quantisation`.
    std::optional<ExportLayout> compactSh = std::nullopt;
    double quantisation = 0;
};

/// Every row of the check.
const std::vector<LayoutCase>& layoutCases();

/// The whole compute shader of a row for an export: #version, the row's `before`, the doc's blocks, the
/// glue and a main() that writes vdblightCheck(points[i], normals[i]) to out[i].
std::string computeShader(const LayoutCase& c, const Manifest& manifest, const std::vector<std::string>& glslBlocks);

}  // namespace vdblight::gpu
