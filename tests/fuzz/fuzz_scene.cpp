// libFuzzer harness: scene loading (loadScene, Assimp) from a file with the extension
// VDBLIGHT_FUZZ_EXTENSION (.obj, .ply, .gltf, .glb, .fbx, .dae, .stl, .off, .x or .3ds: one
// executable each). A loader must
// either return a valid scene or throw one of vdblight's typed errors; any other exception,
// crash, leak or sanitizer report is a finding. scripts/fuzz.sh builds and runs it
// (docs/measurements/robustness.md, "Sanitizers and fuzzing").
#include <cstddef>
#include <cstdint>

#include "fuzz_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string& path = vdblight::fuzz::writeInput(data, size, VDBLIGHT_FUZZ_EXTENSION);
    try {
        const vdblight::Scene scene = vdblight::loadScene(path);
        vdblight::validateScene(scene);  // what loadScene returns satisfies every invariant
        (void)scene.contentHash();
        (void)scene.bounds();
    } catch (const vdblight::Error&) {
        // rejected with a typed, one-line error: the expected outcome for most inputs
    }
    return 0;
}
