// Principal component analysis of row vectors (Leonhardt & Bohn eq. 7-9), Eigen inside,
// plain vectors outside so that callers do not need Eigen's headers. Internal to the prt module
// (tests include it as "../libvdblight/src/prt/pca.h"); the basis type a PrtData holds,
// PcaBasis, is public in prt.h.
#pragma once

#include <cstddef>
#include <vector>

#include "vdblight/prt/prt.h"

namespace vdblight {

/// PCA of the n x dim row-major matrix `rows`: the mean row and the first
/// min(keep, n, dim) right singular vectors of the centred matrix (Eigen BDCSVD).
/// With centre == false the mean is zero and the SVD is of `rows` itself.
/// Throws ValueError on n == 0, dim == 0 or keep < 0.
PcaBasis fitPca(const std::vector<float>& rows, int n, int dim, int keep, bool centre = true);

/// Eq. 8: coefficients (count values) of one row `x` (dim values).
void pcaProject(const PcaBasis& b, const float* x, float* coeffs);

/// Eq. 9: the row (dim values) from its coefficients.
void pcaReconstruct(const PcaBasis& b, const float* coeffs, float* x);

/// Eq. 9 for one component `t` of the row only (the run-time lookup).
inline float pcaReconstructAt(const PcaBasis& b, const float* coeffs, int t) {
    float v = b.mean[std::size_t(t)];
    for (int k = 0; k < b.count; ++k) v += coeffs[k] * b.vectors[std::size_t(k) * std::size_t(b.dim) + std::size_t(t)];
    return v;
}

}  // namespace vdblight
