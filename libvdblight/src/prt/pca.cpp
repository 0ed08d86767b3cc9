// PCA by Eigen's divide-and-conquer SVD of the centred matrix (eq. 7).
#include "pca.h"

#include <Eigen/Dense>
#include <algorithm>

#include "vdblight/core/errors.h"

namespace vdblight {

PcaBasis fitPca(const std::vector<float>& rows, int n, int dim, int keep, bool centre) {
    if (n <= 0 || dim <= 0) throw ValueError("PCA needs at least one row and one column");
    if (keep < 0) throw ValueError("PCA: number of components must not be negative");
    if (rows.size() != std::size_t(n) * std::size_t(dim)) throw ValueError("PCA: matrix size mismatch");
    using Mat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    Mat a(n, dim);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < dim; ++j) a(i, j) = rows[std::size_t(i) * std::size_t(dim) + std::size_t(j)];
    const Eigen::RowVectorXd mu = centre ? Eigen::RowVectorXd(a.colwise().mean()) : Eigen::RowVectorXd::Zero(dim);
    a.rowwise() -= mu;

    PcaBasis b;
    b.dim = dim;
    b.mean.resize(std::size_t(dim));
    for (int j = 0; j < dim; ++j) b.mean[std::size_t(j)] = float(mu(j));
    const int rank = std::min(n, dim);
    b.count = std::min(keep, rank);
    Eigen::BDCSVD<Mat> svd(a, Eigen::ComputeThinV);
    const Eigen::VectorXd& sv = svd.singularValues();
    b.singularValues.assign(sv.data(), sv.data() + sv.size());
    const Eigen::MatrixXd& v = svd.matrixV();  // dim x rank, columns = right singular vectors
    b.vectors.resize(std::size_t(b.count) * std::size_t(dim));
    for (int k = 0; k < b.count; ++k) {
        // Fix the sign (largest component positive) so that the basis is reproducible.
        Eigen::Index arg = 0;
        v.col(k).cwiseAbs().maxCoeff(&arg);
        const double sign = v(arg, k) < 0 ? -1.0 : 1.0;
        for (int j = 0; j < dim; ++j) b.vectors[std::size_t(k) * std::size_t(dim) + std::size_t(j)] = float(sign * v(j, k));
    }
    return b;
}

void pcaProject(const PcaBasis& b, const float* x, float* coeffs) {
    for (int k = 0; k < b.count; ++k) {
        const float* row = b.vectors.data() + std::size_t(k) * std::size_t(b.dim);
        double s = 0;
        for (int j = 0; j < b.dim; ++j) s += double(x[j] - b.mean[std::size_t(j)]) * row[j];
        coeffs[k] = float(s);
    }
}

void pcaReconstruct(const PcaBasis& b, const float* coeffs, float* x) {
    for (int j = 0; j < b.dim; ++j) x[j] = b.mean[std::size_t(j)];
    for (int k = 0; k < b.count; ++k) {
        const float* row = b.vectors.data() + std::size_t(k) * std::size_t(b.dim);
        for (int j = 0; j < b.dim; ++j) x[j] += coeffs[k] * row[j];
    }
}

}  // namespace vdblight
