#ifndef ddfem_solver_sparse_cholesky_h
#define ddfem_solver_sparse_cholesky_h

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <memory>

namespace ddfem::solver
{
  using namespace dealii;

  /**
   * Sparse Cholesky factorization of a symmetric positive definite matrix
   * with CHOLMOD (SuiteSparse; the better of an AMD and a METIS ordering):
   * L L^T, supernodal, or simplicial for small or very sparse matrices, as
   * CHOLMOD chooses. The ordering and the structure of L are computed by
   * analyze(), or by the first factorization after construction or clear();
   * later factorizations (the Newton tangents of one model, the penalties of a
   * definiteness check: same sparsity pattern) only do the numerical work.
   * Its solve can precondition an iterative solver with the factor of an
   * earlier matrix.
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

    /// Drops the factor and frees its values, but keeps the ordering and
    /// the structure of L: the next factorize() of a matrix with the same
    /// sparsity pattern (the tangent after a material edit) does only the
    /// numerical work.
    void
    drop_factor();

    /// The number of values (8 bytes each) the factor holds now: 0 after
    /// clear(), drop_factor() or a factorize() that returned false.
    std::size_t
    values_held() const;

    /**
     * Computes the ordering and the structure of L for the sparsity pattern
     * of @p K, unless they are held already, and returns the number of
     * values L will store (8 bytes each; the factorization's peak memory is
     * larger): +infinity, and no structure held, if they are more than
     * CHOLMOD's 32-bit indices count (about 2.1e9). Throws std::bad_alloc
     * if CHOLMOD runs out of memory.
     */
    double
    analyze(const SparseMatrix<double> &K);

    /**
     * Factorizes the symmetric matrix @p K, reading its lower triangle
     * (the entries with column <= row, diagonal included; CHOLMOD takes
     * them as the upper triangle of the transpose, the same matrix).
     * Returns false, and holds no factor (nor its values), where @p K is not
     * positive definite (a pivot that is not positive) or has an entry that is
     * not finite. Throws std::bad_alloc if CHOLMOD runs out of memory,
     * std::runtime_error if it fails otherwise (a factor too large for its
     * indices), ExcMessage if @p K's sparsity pattern is not the analyzed
     * one.
     */
    bool
    factorize(const SparseMatrix<double> &K);

    /// Whether a factor is held.
    bool
    factorized() const;

    /**
     * The smallest ratio of a pivot (L_jj^2) to the
     * diagonal entry of K it came from (in CHOLMOD's ordering), from the
     * last successful factorize(): in (0, 1] for a positive definite K,
     * at round-off level if K is singular in exact arithmetic.
     */
    double
    smallest_pivot_ratio() const;

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
