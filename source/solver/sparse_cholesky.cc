#include <cholmod.h>
#include <ddfem/solver/sparse_cholesky.h>

#include <stdexcept>
#include <string>

namespace ddfem::solver
{
  struct SparseCholesky::Data
  {
    cholmod_common  common;
    cholmod_factor *factor = nullptr;
    bool            valid  = false;
  };



  SparseCholesky::SparseCholesky()
    : data(std::make_unique<Data>())
  {
    cholmod_start(&data->common);
    data->common.print = 0;
  }



  SparseCholesky::~SparseCholesky()
  {
    clear();
    cholmod_finish(&data->common);
  }



  void
  SparseCholesky::clear()
  {
    if (data->factor != nullptr)
      cholmod_free_factor(&data->factor, &data->common);
    data->valid = false;
  }



  bool
  SparseCholesky::factorize(const SparseMatrix<double> &K)
  {
    cholmod_common &c = data->common;
    const int       n = K.m();
    data->valid       = false;

    // Row r of the symmetric K is its column r; CHOLMOD reads the entries
    // of column r on and above the diagonal (stype 1).
    std::size_t nnz = 0;
    for (int r = 0; r < n; ++r)
      for (auto entry = K.begin(r); entry != K.end(r); ++entry)
        nnz += (static_cast<int>(entry->column()) <= r);
    cholmod_sparse *A =
      cholmod_allocate_sparse(n, n, nnz, false, true, 1, CHOLMOD_REAL, &c);
    if (A == nullptr)
      throw std::runtime_error("CHOLMOD: out of memory for the matrix");
    int        *columns = static_cast<int *>(A->p);
    int        *rows    = static_cast<int *>(A->i);
    double     *values  = static_cast<double *>(A->x);
    std::size_t k       = 0;
    for (int r = 0; r < n; ++r)
      {
        columns[r] = k;
        for (auto entry = K.begin(r); entry != K.end(r); ++entry)
          if (static_cast<int>(entry->column()) <= r)
            {
              rows[k]   = entry->column();
              values[k] = entry->value();
              ++k;
            }
      }
    columns[n] = k;

    if (data->factor == nullptr)
      {
        data->factor = cholmod_analyze(A, &c);
        if (data->factor == nullptr)
          {
            cholmod_free_sparse(&A, &c);
            throw std::runtime_error("CHOLMOD: the analysis failed (memory?)");
          }
      }
    Assert(data->factor->n == static_cast<std::size_t>(n),
           ExcMessage("The sparsity pattern changed without clear()."));
    cholmod_factorize(A, data->factor, &c);
    cholmod_free_sparse(&A, &c);
    // Errors are negative (out of memory, a factor too large for 32-bit
    // indices); CHOLMOD_NOT_POSDEF is a warning.
    if (c.status < CHOLMOD_OK)
      throw std::runtime_error("CHOLMOD: the factorization of a " +
                               std::to_string(n) +
                               "-unknown matrix failed (status " +
                               std::to_string(c.status) + "; out of memory?)");
    data->valid = (c.status == CHOLMOD_OK);
    return data->valid;
  }



  bool
  SparseCholesky::factorized() const
  {
    return data->valid;
  }



  void
  SparseCholesky::vmult(Vector<double> &x, const Vector<double> &b) const
  {
    Assert(data->valid, ExcMessage("No Cholesky factor to solve with."));
    cholmod_common &c = data->common;
    cholmod_dense   B;
    B.nrow           = b.size();
    B.ncol           = 1;
    B.nzmax          = b.size();
    B.d              = b.size();
    B.x              = const_cast<double *>(b.begin());
    B.z              = nullptr;
    B.xtype          = CHOLMOD_REAL;
    B.dtype          = CHOLMOD_DOUBLE;
    cholmod_dense *X = cholmod_solve(CHOLMOD_A, data->factor, &B, &c);
    if (X == nullptr)
      throw std::runtime_error("CHOLMOD: the solve failed (memory?)");
    const double *values = static_cast<const double *>(X->x);
    std::copy(values, values + b.size(), x.begin());
    cholmod_free_dense(&X, &c);
  }
} // namespace ddfem::solver
