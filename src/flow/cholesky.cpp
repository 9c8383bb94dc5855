#include "ricci/flow/cholesky.hpp"

#include <Eigen/SparseCholesky>

#ifdef RICCI_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

#include "ricci/errors.hpp"

namespace ricci {

struct SparseCholesky::Impl {
  bool use_cholmod = false;
  bool analyzed = false;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> eigen;
#ifdef RICCI_HAVE_CHOLMOD
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> cholmod;
#endif
};

SparseCholesky::SparseCholesky(bool use_cholmod) : impl_(std::make_unique<Impl>()) {
  impl_->use_cholmod = use_cholmod && cholmod_available();
#ifdef RICCI_HAVE_CHOLMOD
  // The library never prints: CHOLMOD reports through info(), not on stderr.
  impl_->cholmod.cholmod().print = 0;
#endif
}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

bool SparseCholesky::cholmod_available() {
#ifdef RICCI_HAVE_CHOLMOD
  return true;
#else
  return false;
#endif
}

const char* SparseCholesky::backend() const {
  return impl_->use_cholmod ? "cholmod-supernodal" : "eigen-simplicial-ldlt";
}

bool SparseCholesky::analyzed() const {
  return impl_->analyzed;
}

void SparseCholesky::analyze(const Eigen::SparseMatrix<double>& A) {
#ifdef RICCI_HAVE_CHOLMOD
  if (impl_->use_cholmod) {
    impl_->cholmod.analyzePattern(A);
    if (impl_->cholmod.info() != Eigen::Success) {
      throw SolverError("SparseCholesky::analyze: CHOLMOD's symbolic analysis failed");
    }
    impl_->analyzed = true;
    return;
  }
#endif
  impl_->eigen.analyzePattern(A);
  if (impl_->eigen.info() != Eigen::Success) {
    throw SolverError("SparseCholesky::analyze: symbolic analysis failed");
  }
  impl_->analyzed = true;
}

void SparseCholesky::factorize(const Eigen::SparseMatrix<double>& A) {
  if (!impl_->analyzed) analyze(A);
#ifdef RICCI_HAVE_CHOLMOD
  if (impl_->use_cholmod) {
    impl_->cholmod.factorize(A);
    if (impl_->cholmod.info() != Eigen::Success) {
      throw SolverError(
          "SparseCholesky::factorize: the matrix is not positive definite "
          "(CHOLMOD's numeric factorisation failed)");
    }
    return;
  }
#endif
  impl_->eigen.factorize(A);
  if (impl_->eigen.info() != Eigen::Success || (impl_->eigen.vectorD().array() <= 0).any()) {
    throw SolverError("SparseCholesky::factorize: the matrix is not positive definite");
  }
}

Eigen::VectorXd SparseCholesky::solve(const Eigen::VectorXd& b) const {
#ifdef RICCI_HAVE_CHOLMOD
  if (impl_->use_cholmod) return impl_->cholmod.solve(b);
#endif
  return impl_->eigen.solve(b);
}

}  // namespace ricci
