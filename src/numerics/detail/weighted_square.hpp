#pragma once
/// \file
/// Internal: A D A for a symmetric sparse A (a mesh Laplacian) and diagonal D, written into a
/// pattern computed once. The free seams' systems are all of this form (L M^-1 L, L W L): their
/// pattern is that of L L whatever D is, so the pattern is built once and each system is a pass
/// over the values. Eigen's general sparse product sorts and allocates for every product, and its
/// sums copy the matrix once more for each term: on bob (5.3k vertices) the squared Laplacian
/// took 4.3 ms that way and the Dirichlet system 7.6 ms; here the pattern takes 1.4 ms and each
/// system's values 0.5 ms.

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace ricci::numerics_detail {

/// The pattern of A A for a square, symmetric A (compressed, column-major): every entry that a
/// product of A's stored entries reaches, exact cancellations included, and the whole diagonal
/// (a vertex of no face has an empty column). Values are 0; both triangles are stored.
Eigen::SparseMatrix<double> square_pattern(const Eigen::SparseMatrix<double>& A);

/// Sets the values of `into` (its pattern square_pattern(A)'s, or one holding it) to those of
/// A diag(d) A. Each entry sums A(i,k) A(k,j) d_k over k in increasing order, the same products
/// for (i,j) and (j,i), so the result is symmetric to the bit when A is.
void set_weighted_square(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& d,
                         Eigen::SparseMatrix<double>& into);

/// Adds scale * A into `into`, whose pattern holds A's (both compressed, column-major).
void add_into_pattern(const Eigen::SparseMatrix<double>& A, double scale,
                      Eigen::SparseMatrix<double>& into);

}  // namespace ricci::numerics_detail
