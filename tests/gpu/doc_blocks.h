// The code blocks of Markdown documents, read when the test runs: the GPU-driver check
// compiles and runs the GLSL of the engine pages (docs/engines.md, docs/engine_layouts.md,
// docs/engine_visibility.md) itself, so the documents cannot drift from what is tested. A
// block is found by a declaration it holds (e.g. the name of the function it defines), which
// is what a reader of the pages looks for too.
#pragma once

#include <string>
#include <vector>

namespace vdblight::gpu {

/// Every fenced block of `markdown` opened by ```LANGUAGE (e.g. "glsl", "hlsl"), in order.
std::vector<std::string> fencedBlocks(const std::string& markdown, const std::string& language);

/// The one block of `blocks` that contains `declaration` (e.g. "vec3 vdblightIrradiance(");
/// throws std::runtime_error if none does, or more than one.
const std::string& blockDeclaring(const std::vector<std::string>& blocks, const std::string& declaration);

/// The engine pages of this source tree (kEngineDocs), one after the other: a block is found
/// by what it declares, whichever page it is on.
std::string readEngineDocs();

/// The pages readEngineDocs reads, relative to docs/.
extern const char* const kEngineDocs[3];
/// The text of docs/NAME of this source tree (e.g. "shadow_visibility.md").
std::string readDoc(const std::string& name);

}  // namespace vdblight::gpu
