#ifndef ddfem_solver_sparse_cholesky_h
#define ddfem_solver_sparse_cholesky_h

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <memory>

namespace ddfem::solver
{
  using namespace dealii;

  /**
   * Sparse Cholesky factorization K = L L^T of a symmetric positive definite
   * matrix with CHOLMOD (SuiteSparse, supernodal, METIS or AMD ordering).
   * The ordering and the structure of L are computed by the first
   * factorization after construction or clear(); later factorizations (the
   * Newton tangents of one model, same sparsity pattern) only do the
   * numerical work. Its solve can precondition
   * an iterative solver with the factor of an earlier matrix.
   */
  class SparseCholesky
  {
  public:
    /// Starts CHOLMOD.
    SparseCholesky();

    /// Frees the factor and ends CHOLMOD.
    ~SparseCholesky();

    /// Not copyable: it owns the factor.
    SparseCholesky(const SparseCholesky &) = delete;
    /// Not copyable.
    SparseCholesky &
    operator=(const SparseCholesky &) = delete;

    /// Frees the factor and its structure; call it before factorizing a
    /// matrix with another sparsity pattern.
    void
    clear();

    /**
     * Factorizes the symmetric matrix @p K, reading its upper triangle.
     * Returns false, and holds no factor, if @p K is not positive definite.
     * Throws std::runtime_error if CHOLMOD fails otherwise (out of memory).
     */
    bool
    factorize(const SparseMatrix<double> &K);

    /// Whether a factor is held.
    bool
    factorized() const;

    /// @p x = K^{-1} @p b with the factor of the last factorize().
    void
    vmult(Vector<double> &x, const Vector<double> &b) const;

  private:
    /// CHOLMOD's workspace, the matrix and its factor, whether the factor
    /// is valid, and the solves' vectors.
    struct Data;
    std::unique_ptr<Data> data;
  };
} // namespace ddfem::solver

#endif
