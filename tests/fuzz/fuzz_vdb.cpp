// libFuzzer harness: .vdb reading. The input is written to a .vdb file and given to what
// `vdblight info` and `query` do: isPrtFile (info's first question, through the PRT reader's
// open), inspectVolumeFile (the grid listing), readVolume (every
// structural check of docs/format.md) and, for a volume that passes, IrradianceQuery at a few
// points and normals (so that the reader's checks are enough for the lookups). Rejection must
// be a typed vdblight error; any other exception, crash, leak or sanitizer report is a finding.
#include <tbb/global_control.h>

#include <cstddef>
#include <cstdint>

#include "fuzz_util.h"
#include "../../libvdblight/src/volume/content_hash.h"  // internal: stampContentUuid
#include "vdblight/core/errors.h"
#include "vdblight/prt/prt.h"
#include "vdblight/query/query.h"
#include "vdblight/volume/vdb_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    using namespace vdblight;
    // One thread: how a parallel read splits its work varies from run to run, and with it the
    // coverage counts libFuzzer keeps inputs for, so the same seed grew a different corpus.
    static tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
    const std::string& path = fuzz::writeInput(data, size, ".vdb");
    // A mutated file would fail the content-hash check (readVolume refuses a file whose
    // content-derived UUID its content does not give) before OpenVDB parses anything. Stamping
    // the UUID its bytes give lets the fuzzer explore what a crafted file reaches behind that
    // check; the check itself is tested in reproducible_test.cpp.
    try {
        vdb_detail::stampContentUuid(path);
    } catch (const std::exception&) {  // no OpenVDB header: the reader refuses it below
    }
    try {
        (void)isPrtFile(path);
    } catch (const Error&) {
    }
    try {
        (void)inspectVolumeFile(path);
    } catch (const Error&) {
    }
    try {
        const Volume volume = readVolume(path);
        const IrradianceQuery query(volume);
        const Bounds b = query.bounds();
        const Vec3f normals[3] = {Vec3f(0, 1, 0), Vec3f(0.6f, -0.8f, 0), Vec3f(0, 0, -1)};
        for (int k = 0; k < 5; ++k) {
            const double t = k / 4.0;  // corners, centre and outside (clamped)
            const Vec3d x = b.lo + (b.hi - b.lo) * (1.5 * t - 0.25);
            for (const Vec3f& n : normals) {
                (void)query.irradiance(Vec3f(x), n);
            }
        }
    } catch (const Error&) {
    }
    return 0;
}
