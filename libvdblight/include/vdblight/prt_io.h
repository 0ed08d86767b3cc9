// PRT files: the samples as an OpenVDB PointDataGrid and the bases and transfer matrices as
// float grids used as sparse matrices (docs/format.md, "PRT files").
#pragma once

#include <cstdint>
#include <string>

#include "vdblight/prt.h"

namespace vdblight {

struct PrtWriteOptions {
    bool quantize = true;        ///< 16-bit storage (half floats) for coefficients and matrices
    float sparseThreshold = 0;   ///< matrix entries with |v| <= threshold * max|row| are dropped
};

/// Writes atomically (temporary file + rename). Throws IoError / ValueError.
void writePrt(const PrtData& prt, const std::string& path, const PrtWriteOptions& options = {});

/// Reads a file written by writePrt. Throws IoError, or FormatError if it is not a PRT file
/// (e.g. an SH volume).
PrtData readPrt(const std::string& path);

/// True if the file's metadata says it is a PRT file (FormatError if it is no .vdb at all).
bool isPrtFile(const std::string& path);

struct PrtFileInfo {
    uint64_t fileBytes = 0;
    uint64_t samples = 0, clusters = 0;
    uint64_t values = 0;         ///< stored numbers (coefficients, bases, matrices)
    uint64_t droppedValues = 0;  ///< entries dropped as near zero (sparse storage)
    uint64_t bytesFloat32 = 0;   ///< what the values take as 32-bit floats, dense
    uint64_t bytesStored = 0;    ///< what they take as stored (16-bit if quantised, sparse)
};
PrtFileInfo inspectPrt(const std::string& path);

/// What `vdblight prt info` lists of a PRT file: scene, samples and clusters, visibility and
/// direct-light bases, transfer, relightable volume, values and bytes stored, bake times.
std::string prtInfoText(const std::string& path);

}  // namespace vdblight
