// The code blocks of a Markdown document, read when the test runs: the GPU-driver check
// compiles and runs the GLSL of docs/engines.md itself, so the document cannot drift from
// what is tested. A block is found by a declaration it holds (e.g. the name of the function
// it defines), which is what a reader of the page looks for too.
#pragma once

#include <string>
#include <vector>

namespace vdblight::gpu {

/// Every fenced block of `markdown` opened by ```LANGUAGE (e.g. "glsl", "hlsl"), in order.
std::vector<std::string> fencedBlocks(const std::string& markdown, const std::string& language);

/// The one block of `blocks` that contains `declaration` (e.g. "vec3 vdblightIrradiance(");
/// throws std::runtime_error if none does, or more than one.
const std::string& blockDeclaring(const std::vector<std::string>& blocks, const std::string& declaration);

/// The text of docs/engines.md of this source tree.
std::string readEnginesDoc();
/// The text of docs/NAME of this source tree (e.g. "shadow_visibility.md").
std::string readDoc(const std::string& name);

}  // namespace vdblight::gpu
