#include <cholmod.h>
#include <ddfem/solver/sparse_cholesky.h>

#include <stdexcept>
#include <string>

namespace ddfem::solver
{
  struct SparseCholesky::Data
  {
    cholmod_common common;
    /// The upper triangle of the matrix in CHOLMOD's format: its structure
    /// is built once per sparsity pattern, its values at every
    /// factorization.
    cholmod_sparse *matrix = nullptr;
    cholmod_factor *factor = nullptr;
    bool            valid  = false;
    /// The solution and the workspace of the solves, kept between them.
    cholmod_dense *x = nullptr, *y = nullptr, *e = nullptr;
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
    cholmod_common &c = data->common;
    if (data->matrix != nullptr)
      cholmod_free_sparse(&data->matrix, &c);
    if (data->factor != nullptr)
      cholmod_free_factor(&data->factor, &c);
    for (cholmod_dense **d : {&data->x, &data->y, &data->e})
      if (*d != nullptr)
        cholmod_free_dense(d, &c);
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
    const auto upper = [](const auto &entry) {
      return entry.column() <= static_cast<unsigned int>(entry.row());
    };
    if (data->matrix == nullptr)
      {
        std::size_t nnz = 0;
        for (int r = 0; r < n; ++r)
          for (auto entry = K.begin(r); entry != K.end(r); ++entry)
            nnz += upper(*entry);
        data->matrix =
          cholmod_allocate_sparse(n, n, nnz, false, true, 1, CHOLMOD_REAL, &c);
        if (data->matrix == nullptr)
          throw std::runtime_error("CHOLMOD: out of memory for the matrix");
        int        *columns = static_cast<int *>(data->matrix->p);
        int        *rows    = static_cast<int *>(data->matrix->i);
        std::size_t k       = 0;
        for (int r = 0; r < n; ++r)
          {
            columns[r] = k;
            for (auto entry = K.begin(r); entry != K.end(r); ++entry)
              if (upper(*entry))
                rows[k++] = entry->column();
          }
        columns[n]   = k;
        data->factor = cholmod_analyze(data->matrix, &c);
        if (data->factor == nullptr)
          {
            clear();
            throw std::runtime_error("CHOLMOD: the analysis failed (memory?)");
          }
      }
    Assert(data->matrix->nrow == static_cast<std::size_t>(n),
           ExcMessage("The sparsity pattern changed without clear()."));
    double     *values = static_cast<double *>(data->matrix->x);
    std::size_t k      = 0;
    for (int r = 0; r < n; ++r)
      for (auto entry = K.begin(r); entry != K.end(r); ++entry)
        if (upper(*entry))
          values[k++] = entry->value();

    cholmod_factorize(data->matrix, data->factor, &c);
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
    B.nrow  = b.size();
    B.ncol  = 1;
    B.nzmax = b.size();
    B.d     = b.size();
    B.x     = const_cast<double *>(b.begin());
    B.z     = nullptr;
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    if (!cholmod_solve2(CHOLMOD_A,
                        data->factor,
                        &B,
                        nullptr,
                        &data->x,
                        nullptr,
                        &data->y,
                        &data->e,
                        &c))
      throw std::runtime_error("CHOLMOD: the solve failed (memory?)");
    const double *values = static_cast<const double *>(data->x->x);
    std::copy(values, values + b.size(), x.begin());
  }
} // namespace ddfem::solver
