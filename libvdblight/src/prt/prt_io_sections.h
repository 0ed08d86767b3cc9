// The sections of a PRT file (docs/prt_format.md), one file each, which
// prt_io.cpp's writePrt / readPrt put together:
// - the header: the metadata that says what was baked and how big each part is
//   (prt_io_header.cpp);
// - the samples: a PointDataGrid with one point per surface sample, its visibility
//   coefficients as a point attribute (prt_io_samples.cpp);
// - the matrices: the PCA bases and the transfer matrices as sparse float grids whose
//   voxel (a, b, c) is a matrix entry (prt_io_matrices.cpp).
// A reader checks every count against what the header declared before it trusts it.
#pragma once

#include <cstdint>
#include <string>

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/points/PointDataGrid.h>

#include "vdblight/core/errors.h"
#include "vdblight/prt/prt.h"

namespace vdblight::prt_io {

inline const std::string kP = "vdblight:";
/// 1: one bounce, no version key but prt_format_version; 2: `format_version` and `bounces`.
constexpr int64_t kPrtFormatVersion = 2;

/// Numbers stored and numbers dropped as near zero (the header's values / dropped_values).
struct Counter {
    uint64_t values = 0, dropped = 0;
};

/// A required metadata value; FormatError naming the file and key if it is missing.
template <typename T>
T meta(const openvdb::MetaMap& m, const std::string& key, const std::string& path) {
    auto v = m.getMetadata<openvdb::TypedMetadata<T>>(kP + key);
    if (!v) throw FormatError("'" + path + "' is not a valid PRT file: no metadata " + kP + key);
    return v->value();
}

/// A required grid of the given type; FormatError if it is missing or of another type.
template <typename GridT>
typename GridT::Ptr requireGrid(openvdb::io::File& f, const std::string& name, const std::string& path) {
    if (!f.hasGrid(name)) throw FormatError("'" + path + "' is not a valid PRT file: no grid " + name);
    auto g = openvdb::gridPtrCast<GridT>(f.readGrid(name));
    if (!g) throw FormatError("'" + path + "' is not a valid PRT file: grid " + name + " has the wrong type");
    return g;
}

// --- Header (prt_io_header.cpp) -----------------------------------------------------------

/// The file metadata of `prt`, with the counts of the matrices already built.
openvdb::MetaMap writeHeader(const PrtData& prt, const PrtWriteOptions& options, const Counter& counted);

/// A PrtData with every header field set, the sample arrays sized but not filled, and the
/// volume grid (if any) checked. Throws FormatError for a missing key, an unknown version
/// or sizes that do not fit together.
PrtData readHeader(const openvdb::MetaMap& m, const std::string& path);

// --- Samples (prt_io_samples.cpp) ---------------------------------------------------------

/// The samples as points: P (world: the grid's transform adds the scene origin), N, Cd,
/// area, id, cluster and the visibility coefficients `vis` (16-bit if `quantize`).
openvdb::points::PointDataGrid::Ptr writeSamples(const PrtData& prt, bool quantize);

/// Fills prt.samples (positions, normals, albedo, area, cluster, cluster ranges) and
/// prt.visCoeffs from the point grid, refusing a missing, repeated or out-of-range sample id.
void readSamples(openvdb::io::File& file, PrtData& prt, const std::string& path);

// --- Matrices (prt_io_matrices.cpp) -------------------------------------------------------

struct MatrixGrids {
    openvdb::FloatGrid::Ptr visBasis, lightBasis;
    openvdb::Vec3SGrid::Ptr transfer;
    openvdb::Vec3SGrid::Ptr volumeTransfer;  ///< null without a volume
};

/// The bases and transfer matrices as sparse grids (entries at or below the sparse
/// threshold of their row's largest dropped), counting what is stored and dropped.
/// Throws ValueError for a non-finite entry.
MatrixGrids writeMatrices(const PrtData& prt, const PrtWriteOptions& options, Counter& counted);

/// Fills prt.visBasis, prt.lightBasis, prt.transfer and prt.volumeTransfer (sized by the
/// header and the samples' clusters), refusing an entry outside the declared sizes.
void readMatrices(openvdb::io::File& file, PrtData& prt, const std::string& path);

}  // namespace vdblight::prt_io
