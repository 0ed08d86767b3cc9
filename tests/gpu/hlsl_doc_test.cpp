// Every HLSL block of the engine pages (docs/engine*.md) and of docs/shadow_visibility.md, read when the test runs,
// compiles with glslangValidator's HLSL front end (issue 33: no HLSL driver runs here, so this is what can be
// checked). Each block is wrapped in a tiny compute entry point that calls every `float3 F(float3, float3)` and
// `float F(float3)` function the block defines and writes the result, so nothing is compiled away unchecked.
// A block that #includes headers (the NanoVDB lookup: PNanoVDB.h and shaders/) is a whole
// shader with its own `main`: a C preprocessor expands it first, because glslang's own
// rejects a 64-bit literal that PNanoVDB.h defines (and never uses); DXC's, clang's, takes it.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "gpu/doc_blocks.h"
#include "test_util.h"

using namespace vdblight;

namespace {

// The functions of a block that an engine calls, each with the arguments and the float4 it is
// written as: float3 Name(float3 x, float3 n) (irradiance) and float Name(float3 x) (a light's
// visibility, docs/shadow_visibility.md).
std::vector<std::string> entryFunctions(const std::string& block) {
    static const std::regex irradiance(R"(\nfloat3 (\w+)\(float3 \w+, float3 \w+\))"), visibility(R"(\nfloat (\w+)\(float3 \w+\))");
    std::vector<std::string> calls;
    for (auto it = std::sregex_iterator(block.begin(), block.end(), irradiance); it != std::sregex_iterator(); ++it)
        calls.push_back("float4(" + (*it)[1].str() + "(x, n), 0)");
    for (auto it = std::sregex_iterator(block.begin(), block.end(), visibility); it != std::sregex_iterator(); ++it)
        calls.push_back("float4(" + (*it)[1].str() + "(x), 0, 0, 0)");
    return calls;
}

// `block` wrapped in a compute shader `main` that writes `calls`.
std::string wrapped(const std::string& block, const std::vector<std::string>& calls) {
    std::string s = block + "\nRWStructuredBuffer<float4> vdblightOut;\n[numthreads(64, 1, 1)]\n"
                            "void main(uint3 id : SV_DispatchThreadID)\n{\n"
                            "    float3 x = float3(id) * 0.01, n = normalize(float3(0.3, -0.5, 0.8));\n";
    for (std::size_t k = 0; k < calls.size(); ++k)
        s += "    vdblightOut[id.x * " + std::to_string(calls.size()) + " + " + std::to_string(k) + "] = " + calls[k] + ";\n";
    return s + "}\n";
}

// A whole shader (a block that #includes): expanded by the C preprocessor with the NanoVDB and
// shaders/ include paths, then compiled as written. Returns glslangValidator's status.
int compileWholeShader(const std::string& block, const test::TempDir& dir, std::string* log) {
    const std::string source = dir.file("whole.hlsl"), expanded = dir.file("whole_expanded.hlsl");
    std::ofstream(source) << block;
    // -undef: no predefined macros (`linux`, `unix` would rewrite identifiers); -P: no line markers.
    const std::string preprocess = std::string(VDBLIGHT_PREPROCESSOR) + " -E -P -undef -nostdinc -x c -I" +
                                   VDBLIGHT_NANOVDB_INCLUDE + " -I" + VDBLIGHT_SHADERS_DIR + " " + source + " -o " + expanded;
    if (const int status = test::runCommand(preprocess, log); status != 0) return status;
    // -Od: parsed, checked and turned into SPIR-V without the optimiser's legalisation passes,
    // which take 7 CPU s on the 2 000 expanded lines (0.1 s without).
    return test::runCommand(std::string(VDBLIGHT_GLSLANG) + " -D -V -Od -e main -S comp -o " + dir.file("out.spv") + " " + expanded,
                            log);
}

}  // namespace

TEST(HlslDoc, EveryBlockCompilesWithGlslangsHlslFrontEnd) {
    const std::string validator = VDBLIGHT_GLSLANG;
    ASSERT_FALSE(validator.empty() || validator.find("NOTFOUND") != std::string::npos)
        << "glslangValidator not found: scripts/setup.sh installs glslang-tools";
    const std::vector<std::string> blocks =
        gpu::fencedBlocks(gpu::readEngineDocs() + gpu::readDoc("shadow_visibility.md"), "hlsl");
    ASSERT_GE(blocks.size(), 3u) << "docs/engine*.md: the sh2-packed, sh:N and visibility-aware HLSL";
    // The shadow edges' second edge (issue 32: "the exports carry it, with a shader"): the twin
    // of the strips GLSL, compiled below like every block.
    EXPECT_NO_THROW(gpu::blockDeclaring(blocks, "float VdblightStripVisibility(float3 uvw, float filtered)"))
        << "docs/shadow_visibility.md: the HLSL of the strips lookup";
    test::TempDir dir;
    int compiled = 0;
    int whole = 0;
    for (std::size_t b = 0; b < blocks.size(); ++b) {
        if (blocks[b].find("#include") != std::string::npos) {
            std::string log;
            EXPECT_EQ(compileWholeShader(blocks[b], dir, &log), 0) << log << "\n" << blocks[b];
            ++whole, ++compiled;
            continue;
        }
        const std::vector<std::string> functions = entryFunctions(blocks[b]);
        ASSERT_FALSE(functions.empty()) << "HLSL block " << b << " defines no float3 F(float3, float3) or float F(float3):\n"
                                        << blocks[b];
        const std::string file = dir.file("block" + std::to_string(b) + ".hlsl");
        std::ofstream(file) << wrapped(blocks[b], functions);
        // The sh:N block is compiled for every order it documents; the others as written.
        const bool perOrder = blocks[b].find("VDBLIGHT_SH_ORDER") != std::string::npos;
        for (int order = perOrder ? 1 : 0; order <= (perOrder ? 4 : 0); ++order) {
            const std::string define = perOrder ? " -DVDBLIGHT_SH_ORDER=" + std::to_string(order) : "";
            std::string log;
            const std::string command = validator + " -D -V -e main -S comp" + define + " -o " + dir.file("out.spv") + " " + file;
            EXPECT_EQ(test::runCommand(command, &log), 0) << command << "\n" << log << "\n" << wrapped(blocks[b], functions);
            ++compiled;
        }
        // The VDBLIGHT_SH1 variant of the sh2-packed block.
        if (blocks[b].find("VDBLIGHT_SH1") != std::string::npos) {
            std::string log;
            const std::string command = validator + " -D -V -e main -S comp -DVDBLIGHT_SH1 -o " + dir.file("out.spv") + " " + file;
            EXPECT_EQ(test::runCommand(command, &log), 0) << command << "\n" << log;
            ++compiled;
        }
    }
    EXPECT_GE(whole, 1) << "docs/engines.md: the NanoVDB lookup's HLSL (a block that #includes PNanoVDB.h)";
    std::printf("%zu HLSL blocks of the engine pages and shadow_visibility.md (%d whole shaders), %d compilations\n", blocks.size(), whole, compiled);
}
