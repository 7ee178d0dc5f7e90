#include <cholmod.h>
#include <ddfem/solver/sparse_cholesky.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

namespace ddfem::solver
{
  namespace
  {
    /// Whether an entry of row r of K lies in column r of CHOLMOD's matrix
    /// (K read column by column) on or above the diagonal: column <= row.
    template <typename Entry>
    bool
    is_upper(const Entry &entry)
    {
      return entry.column() <= static_cast<unsigned int>(entry.row());
    }

    /**
     * Throws for CHOLMOD's failure with status @p status in @p step of an
     * @p n-unknown matrix: std::bad_alloc when it ran out of memory, as
     * every other allocation would, and a message that names the remedy
     * when the factor has more entries than CHOLMOD's 32-bit indices count.
     */
    [[noreturn]] void
    throw_failure(const int status, const std::string &step, const int n)
    {
      if (status == CHOLMOD_OUT_OF_MEMORY)
        throw std::bad_alloc();
      if (status == CHOLMOD_TOO_LARGE)
        throw std::runtime_error(
          "CHOLMOD: the Cholesky factor of a " + std::to_string(n) +
          "-unknown matrix has more entries than its 32-bit indices "
          "count; use Linear solver/Type = cg-amg, which needs no factor");
      throw std::runtime_error(
        "CHOLMOD: the " + step + " of a " + std::to_string(n) +
        "-unknown matrix failed (status " + std::to_string(status) + ")");
    }



    /// Frees the values of @p factor, keeping its ordering and structure:
    /// the symbolic factor of an analysis, which cholmod_factorize() fills.
    void
    free_values(cholmod_factor *factor, cholmod_common &c)
    {
      if (factor != nullptr && factor->xtype != CHOLMOD_PATTERN)
        cholmod_change_factor(CHOLMOD_PATTERN,
                              factor->is_ll,
                              factor->is_super,
                              true,
                              true,
                              factor,
                              &c);
    }
  } // namespace



  struct SparseCholesky::Data
  {
    cholmod_common common;
    /// The upper triangle of the matrix in CHOLMOD's format: its structure
    /// is built once per sparsity pattern, its values at every
    /// factorization.
    cholmod_sparse *matrix = nullptr;
    cholmod_factor *factor = nullptr;
    /// The values L will store, from the analysis.
    double factor_values = 0;
    bool   valid         = false;
    /// The solution and the workspace of the solves, kept between them.
    cholmod_dense *x = nullptr, *y = nullptr, *e = nullptr;
  };



  SparseCholesky::SparseCholesky()
    : data(std::make_unique<Data>())
  {
    cholmod_start(&data->common);
    data->common.print = 0;
    // Simplicial factors as L L^T too, not L D L^T: that fails on a pivot
    // that is not positive, as the supernodal one does, where L D L^T would
    // factorize an indefinite matrix.
    data->common.final_ll = true;
    // Order every matrix with both AMD and METIS's nested dissection and
    // keep the ordering whose factor has fewer entries. CHOLMOD's default
    // tries METIS only after AMD gave a factor with many flops per entry
    // (500), which the fine models' tangents reach and the coarse models'
    // do not, although METIS makes their factorizations a tenth to a third
    // cheaper (doc/fine_solver.md, "cg-cholesky").
    data->common.nmethods           = 2;
    data->common.method[0].ordering = CHOLMOD_AMD;
    data->common.method[1].ordering = CHOLMOD_METIS;
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



  void
  SparseCholesky::drop_factor()
  {
    free_values(data->factor, data->common);
    data->valid = false;
  }



  std::size_t
  SparseCholesky::values_held() const
  {
    const cholmod_factor *L = data->factor;
    if (L == nullptr || L->xtype == CHOLMOD_PATTERN)
      return 0;
    return L->is_super ? L->xsize : L->nzmax;
  }



  double
  SparseCholesky::analyze(const SparseMatrix<double> &K)
  {
    if (data->matrix == nullptr)
      {
        cholmod_common &c = data->common;
        const int       n = K.m();
        // Row r of the symmetric K is its column r; CHOLMOD reads the
        // entries of column r on and above the diagonal (stype 1).
        std::size_t nnz = 0;
        for (int r = 0; r < n; ++r)
          for (auto entry = K.begin(r); entry != K.end(r); ++entry)
            nnz += is_upper(*entry);
        data->matrix =
          cholmod_allocate_sparse(n, n, nnz, false, true, 1, CHOLMOD_REAL, &c);
        // A triangle with more entries than 32-bit indices count has a
        // factor with more still.
        if (data->matrix == nullptr && c.status == CHOLMOD_TOO_LARGE)
          return std::numeric_limits<double>::infinity();
        if (data->matrix == nullptr)
          throw_failure(c.status, "allocation", n);
        int        *columns = static_cast<int *>(data->matrix->p);
        int        *rows    = static_cast<int *>(data->matrix->i);
        std::size_t k       = 0;
        for (int r = 0; r < n; ++r)
          {
            columns[r] = k;
            for (auto entry = K.begin(r); entry != K.end(r); ++entry)
              if (is_upper(*entry))
                rows[k++] = entry->column();
          }
        columns[n]   = k;
        data->factor = cholmod_analyze(data->matrix, &c);
        if (data->factor == nullptr)
          {
            const int status = c.status;
            clear();
            if (status == CHOLMOD_TOO_LARGE)
              return std::numeric_limits<double>::infinity();
            throw_failure(status, "analysis", n);
          }
        // Supernodes store their blocks with the zeros that amalgamation
        // adds (xsize); a simplicial factor holds its nonzeros (lnz).
        data->factor_values =
          data->factor->is_super ? data->factor->xsize : c.lnz;
      }
    return data->factor_values;
  }



  bool
  SparseCholesky::factorize(const SparseMatrix<double> &K)
  {
    cholmod_common &c = data->common;
    const int       n = K.m();
    data->valid       = false;
    if (std::isinf(analyze(K)))
      throw_failure(CHOLMOD_TOO_LARGE, "analysis", n);
    // The values go into the structure of the analyzed pattern: another
    // pattern would write past its end.
    const int  *columns = static_cast<const int *>(data->matrix->p);
    const int  *rows    = static_cast<const int *>(data->matrix->i);
    double     *values  = static_cast<double *>(data->matrix->x);
    bool        same    = data->matrix->nrow == static_cast<std::size_t>(n);
    bool        finite  = true;
    std::size_t k       = 0;
    for (int r = 0; same && r < n; ++r)
      for (auto entry = K.begin(r); same && entry != K.end(r); ++entry)
        if (is_upper(*entry))
          {
            same = k < static_cast<std::size_t>(columns[n]) &&
                   rows[k] == static_cast<int>(entry->column());
            if (same)
              {
                values[k++] = entry->value();
                finite      = finite && std::isfinite(entry->value());
              }
          }
    AssertThrow(same && k == static_cast<std::size_t>(columns[n]),
                ExcMessage("SparseCholesky: the sparsity pattern changed "
                           "without clear()."));
    // CHOLMOD's pivot test (a pivot <= 0) passes a NaN.
    if (!finite)
      {
        drop_factor();
        return false;
      }

    cholmod_factorize(data->matrix, data->factor, &c);
    // Errors are negative; CHOLMOD_NOT_POSDEF is a warning.
    if (c.status < CHOLMOD_OK)
      throw_failure(c.status, "factorization", n);
    // A failed factor is of no use; its values would stay next to the
    // factor of the solver that takes over.
    if (c.status != CHOLMOD_OK)
      drop_factor();
    else
      data->valid = true;
    return data->valid;
  }



  bool
  SparseCholesky::factorized() const
  {
    return data->valid;
  }



  double
  SparseCholesky::smallest_pivot_ratio() const
  {
    Assert(data->valid, ExcMessage("No Cholesky factor to read."));
    const cholmod_factor &L         = *data->factor;
    const cholmod_sparse &K         = *data->matrix;
    const int            *K_columns = static_cast<const int *>(K.p);
    const double         *K_values  = static_cast<const double *>(K.x);
    const double         *L_values  = static_cast<const double *>(L.x);
    const int            *perm      = static_cast<const int *>(L.Perm);
    Assert(L.is_ll, ExcInternalError());
    // The pivot L_jj^2 of column j of L over the diagonal entry of K it
    // came from: row j of L is row perm[j] of K, and column r of K starts
    // with its diagonal entry (deal.II stores it first in row r, which
    // factorize() copies in order).
    const auto ratio = [&](const std::size_t j, const double L_jj) {
      return L_jj * L_jj / K_values[K_columns[perm[j]]];
    };
    double smallest = std::numeric_limits<double>::max();
    if (L.is_super)
      {
        // Supernode s holds columns super[s] to super[s + 1] - 1 as a
        // column-major block of pi[s + 1] - pi[s] rows whose first rows are
        // those columns.
        const int *super = static_cast<const int *>(L.super);
        const int *pi    = static_cast<const int *>(L.pi);
        const int *px    = static_cast<const int *>(L.px);
        for (std::size_t s = 0; s < L.nsuper; ++s)
          for (int j = super[s]; j < super[s + 1]; ++j)
            smallest = std::min(
              smallest,
              ratio(
                j, L_values[px[s] + (j - super[s]) * (pi[s + 1] - pi[s] + 1)]));
      }
    else
      {
        const int *L_columns = static_cast<const int *>(L.p);
        for (std::size_t j = 0; j < L.n; ++j)
          smallest = std::min(smallest, ratio(j, L_values[L_columns[j]]));
      }
    return smallest;
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
      throw_failure(c.status, "solve", b.size());
    const double *values = static_cast<const double *>(data->x->x);
    std::copy(values, values + b.size(), x.begin());
  }
} // namespace ddfem::solver
