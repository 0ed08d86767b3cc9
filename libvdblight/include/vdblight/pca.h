// Principal component analysis of row vectors (Leonhardt & Bohn eq. 7-9), Eigen inside,
// plain vectors outside so that callers do not need Eigen's headers.
#pragma once

#include <cstdint>
#include <vector>

namespace vdblight {

/// An orthonormal basis of `count` row vectors of dimension `dim` plus the mean row.
struct PcaBasis {
    int dim = 0;
    int count = 0;
    std::vector<float> mean;     ///< dim values (eq. 7's mu)
    std::vector<float> vectors;  ///< count x dim, row-major; rows are orthonormal (B of eq. 8)
    std::vector<double> singularValues;  ///< all of them (min(n, dim)), largest first
};

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
