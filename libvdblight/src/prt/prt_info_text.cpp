// What `vdblight prt info` (and `vdblight info` of a PRT file) lists (prt_io.h: prtInfoText):
// samples, clusters, bases, transfer, the relightable volume, sizes before and after
// compression and the bake's times.
#include <iomanip>
#include <sstream>

#include "vdblight/core/interrupter.h"
#include "vdblight/prt/prt.h"

namespace vdblight {

namespace {
std::string formatNumber(double v) {
    std::ostringstream out;
    out << v;
    return out.str();
}
}  // namespace

std::string prtInfoText(const std::string& path) {
    const PrtData prt = readPrt(path);
    const PrtFileInfo info = inspectPrt(path);
    std::ostringstream out;
    out << path << ": PRT file, " << formatBytes(double(info.fileBytes)) << " on disk\n"
        << "  scene " << prt.sceneName << " (" << prt.sceneHash << ")\n"
        << "  " << info.samples << " samples in " << info.clusters << " clusters (radius "
        << prt.samples.radius << ")\n"
        << "  visibility: " << prt.visGrid * prt.visGrid << " directions -> " << prt.visCoeffStride
        << " coefficients\n"
        << "  direct-light basis: " << prt.trainLights << " training lights -> "
        << prt.transferStride - 1 - prt.orientedCoeffs
        << " vectors per cluster"
        << (prt.orientedTraining > 0 ? " (+ " + formatNumber(prt.orientedTraining) +
                                         " one-sided per point light -> " + std::to_string(prt.orientedCoeffs) +
                                         " vectors)"
                                     : std::string())
        << "\n"
        << "  scene origin: " << std::setprecision(15) << prt.origin.x << ", " << prt.origin.y << ", "
        << prt.origin.z << std::setprecision(6) << "\n"
        << "  transfer: " << prt.bounces << (prt.bounces == 1 ? " bounce" : " bounces")
        << (prt.closureNormalise ? ", closure-normalised" : ", raw")
        << (prt.formFactorRays ? " sampled form factors (" + std::to_string(prt.formFactorRays) + " rays per receiver)"
                               : std::string(" disk form factors between all sample pairs"))
        << "\n"
        << "  relightable volume: "
        << (prt.hasVolume() ? std::to_string(prt.volumeGrid.nx) + " x " + std::to_string(prt.volumeGrid.ny) + " x " +
                                  std::to_string(prt.volumeGrid.nz) + " nodes"
                            : std::string("none"))
        << "\n"
        << "  values: " << info.values << " (" << info.droppedValues << " dropped as near zero)\n"
        << "  bytes: " << info.bytesFloat32 << " as dense 32-bit floats, " << info.bytesStored
        << " stored (sparse" << (info.bytesStored * 2 <= info.bytesFloat32 + 8 ? ", 16-bit" : "") << ")\n"
        << "  bake time: samples " << formatSeconds(prt.secondsSamples) << ", visibility "
        << formatSeconds(prt.secondsVisibility) << ", basis " << formatSeconds(prt.secondsBasis)
        << ", transfer " << formatSeconds(prt.secondsTransfer) << "\n";
    return out.str();
}

}  // namespace vdblight
