#include <deal.II/base/geometry_info.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_matrix.h>

#include <ddfem/report/vertex_error.h>
#include <ddfem/solver/sparse_cholesky.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace ddfem::report
{
  std::vector<Tensor<1, 3>>
  vertex_displacements(const solver::Discretization &discretization,
                       const Vector<double>         &u)
  {
    std::vector<Tensor<1, 3>> result(discretization.triangulation.n_vertices());
    for (const auto &cell : discretization.dof_handler.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        for (unsigned int c = 0; c < 3; ++c)
          result[cell->vertex_index(v)][c] = u(cell->vertex_dof_index(v, c));
    return result;
  }



  namespace
  {
    /// The values at @p x of the 8 trilinear shape functions of the
    /// axis-aligned box @p cell.
    template <typename Cell>
    std::array<double, 8>
    trilinear_weights(const Cell &cell, const Point<3> &x)
    {
      const Point<3>     origin = cell->vertex(0);
      const Tensor<1, 3> size   = cell->vertex(7) - origin;
      Point<3>           xi;
      for (unsigned int d = 0; d < 3; ++d)
        xi[d] = (x[d] - origin[d]) / size[d];
      std::array<double, 8> N;
      for (const unsigned int w : cell->vertex_indices())
        N[w] = GeometryInfo<3>::d_linear_shape_function(xi, w);
      return N;
    }

    /// The trilinear field @p u of @p cell's vertex values where its shape
    /// functions take the values @p N.
    template <typename Cell>
    Tensor<1, 3>
    interpolate(const Cell                  &cell,
                const std::array<double, 8> &N,
                const Vector<double>        &u)
    {
      Tensor<1, 3> value;
      for (const unsigned int w : cell->vertex_indices())
        for (unsigned int c = 0; c < 3; ++c)
          value[c] += N[w] * u(cell->vertex_dof_index(w, c));
      return value;
    }

    /// The cells of @p d by active index.
    std::vector<DoFHandler<3>::active_cell_iterator>
    cells_of(const solver::Discretization &d)
    {
      std::vector<DoFHandler<3>::active_cell_iterator> cells;
      for (const auto &cell : d.dof_handler.active_cell_iterators())
        cells.push_back(cell);
      return cells;
    }

    /**
     * Calls @p f(fine vertex index, coarse cell, values of the coarse
     * cell's 8 trilinear shape functions there) once for every vertex of
     * @p fine's mesh, through the first fine cell that has it. The coarse
     * field is continuous, so any coarse cell holding the vertex will do:
     * the one of that fine cell's block.
     */
    template <typename Function>
    void
    for_each_fine_vertex(const scene::VoxelGrid       &grid,
                         const solver::Discretization &fine,
                         const solver::Discretization &coarse,
                         const Function               &f)
    {
      // Another fine model may have any degree: at its own vertices the
      // interpolation of its vertex values is exact.
      AssertThrow(fine.level == 0 &&
                    (coarse.level == 0 || coarse.fe.degree == 1),
                  ExcMessage("The vertex error compares a coarse trilinear "
                             "solution, or another fine one, with a fine "
                             "one."));
      const auto coarse_cells = cells_of(coarse);

      std::vector<bool> done(fine.triangulation.n_vertices(), false);
      for (const auto &cell : fine.triangulation.active_cell_iterators())
        {
          const unsigned int c =
            coarse.cell_of_voxel(grid,
                                 fine.cell_blocks[cell->active_cell_index()]);
          AssertThrow(c != numbers::invalid_unsigned_int,
                      ExcMessage("The coarse model has no cell over a solid "
                                 "voxel of the fine one: both must come from "
                                 "the same voxel grid."));
          const auto &coarse_cell = coarse_cells[c];
          for (const unsigned int v : cell->vertex_indices())
            {
              const unsigned int index = cell->vertex_index(v);
              if (done[index])
                continue;
              done[index] = true;
              f(index,
                coarse_cell,
                trilinear_weights(coarse_cell, cell->vertex(v)));
            }
        }
    }
  } // namespace



  VertexError
  vertex_error(const scene::VoxelGrid       &grid,
               const solver::Discretization &fine,
               const Vector<double>         &u_fine,
               const solver::Discretization &coarse,
               const Vector<double>         &u_coarse)
  {
    const std::vector<Tensor<1, 3>> fine_u = vertex_displacements(fine, u_fine);

    // The rest bounding box of the solid.
    Point<3> lower = fine.triangulation.get_vertices()[0], upper = lower;
    for (const auto &cell : fine.triangulation.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        {
          for (unsigned int d = 0; d < 3; ++d)
            {
              lower[d] = std::min(lower[d], cell->vertex(v)[d]);
              upper[d] = std::max(upper[d], cell->vertex(v)[d]);
            }
        }
    VertexError error;
    for (unsigned int d = 0; d < 3; ++d)
      error.length = std::max(error.length, upper[d] - lower[d]);

    for_each_fine_vertex(
      grid,
      fine,
      coarse,
      [&](const unsigned int           index,
          const auto                  &coarse_cell,
          const std::array<double, 8> &N) {
        const double e =
          (interpolate(coarse_cell, N, u_coarse) - fine_u[index]).norm() /
          error.length;
        // A NaN would leave the maximum as it was.
        AssertThrow(std::isfinite(e),
                    ExcMessage(
                      "The vertex error is not finite at fine vertex " +
                      std::to_string(index) +
                      ": a solution holds a NaN or inf."));
        error.mean += e;
        error.max = std::max(error.max, e);
        ++error.n_vertices;
      });
    error.mean /= std::max<std::size_t>(1, error.n_vertices);
    return error;
  }



  double
  max_solid_displacement(const scene::VoxelGrid       &grid,
                         const solver::Discretization &model,
                         const Vector<double>         &u)
  {
    AssertThrow(model.fe.degree == 1,
                ExcMessage("max_solid_displacement() reads a trilinear "
                           "field."));
    const auto   cells = cells_of(model);
    const double h     = grid.voxel_size();
    double       max_u = 0;
    for (std::size_t v = 0; v < grid.n_voxels(); ++v)
      if (grid[v] != scene::void_id)
        {
          const auto  ijk  = grid.coordinates(v);
          const auto &cell = cells[model.cell_of_voxel(grid, v)];
          for (const unsigned int corner : GeometryInfo<3>::vertex_indices())
            {
              Point<3> x;
              for (unsigned int d = 0; d < 3; ++d)
                x[d] = (ijk[d] + ((corner >> d) & 1)) * h;
              max_u = std::max(
                max_u, interpolate(cell, trilinear_weights(cell, x), u).norm());
            }
        }
    return max_u;
  }



  GridFit
  grid_fit(const scene::VoxelGrid       &grid,
           const solver::Discretization &fine,
           const Vector<double>         &u_fine,
           const solver::Discretization &coarse)
  {
    // The field's nodal values are vertex values: a trilinear element.
    Assert(coarse.fe.degree == 1, ExcNotImplemented());
    // Stop once the bound is within 0.2 % of the mean error, once the mean
    // is at round-off, or after 500 steps.
    const double       tolerance      = 2e-3;
    const unsigned int max_iterations = 500;
    // The weights are the same for the three components: the fit solves a
    // scalar problem over the coarse vertices three times.
    DoFHandler<3> vertices(coarse.triangulation);
    vertices.distribute_dofs(FE_Q<3>(1));

    // The scalar unknowns of every coarse cell's vertices.
    std::vector<std::array<types::global_dof_index, 8>> cell_vertices(
      coarse.triangulation.n_active_cells());
    for (const auto &cell : vertices.active_cell_iterators())
      for (const unsigned int w : cell->vertex_indices())
        cell_vertices[cell->active_cell_index()][w] =
          cell->vertex_dof_index(w, 0);

    // Every fine vertex once: its displacement, its coarse cell and the
    // values of that cell's shape functions there.
    struct Sample
    {
      Tensor<1, 3>          f;
      unsigned int          cell;
      std::array<double, 8> N;
    };
    const std::vector<Tensor<1, 3>> fine_u = vertex_displacements(fine, u_fine);
    std::vector<Sample>             samples;
    for_each_fine_vertex(
      grid,
      fine,
      coarse,
      [&](const unsigned int           index,
          const auto                  &coarse_cell,
          const std::array<double, 8> &N) {
        samples.push_back({fine_u[index], coarse_cell->active_cell_index(), N});
      });
    std::array<Vector<double>, 3> a, b;
    const auto distance = [&a, &cell_vertices](const Sample &s) {
      Tensor<1, 3> u;
      for (unsigned int w = 0; w < 8; ++w)
        for (unsigned int c = 0; c < 3; ++c)
          u[c] += s.N[w] * a[c](cell_vertices[s.cell][w]);
      return (u - s.f).norm();
    };

    DynamicSparsityPattern dsp(vertices.n_dofs());
    DoFTools::make_sparsity_pattern(vertices, dsp);
    SparsityPattern pattern;
    pattern.copy_from(dsp);
    SparseMatrix<double>                M(pattern);
    std::vector<std::array<double, 64>> local(cell_vertices.size());
    solver::SparseCholesky              cholesky;
    GridFit                             fit;
    std::vector<double> weights(samples.size(), 1.), r(samples.size());
    double              delta = 0, scale = 0;
    const double        n = std::max<std::size_t>(1, samples.size());
    for (const Sample &s : samples)
      scale = std::max(scale, s.f.norm());
    for (unsigned int c = 0; c < 3; ++c)
      {
        a[c].reinit(vertices.n_dofs());
        b[c].reinit(vertices.n_dofs());
      }
    for (fit.iterations = 1; fit.iterations <= max_iterations; ++fit.iterations)
      {
        // The weighted normal equations M a_c = b_c of
        // min sum_v w_v |sum_i a_i N_i(x_v) - u_fine(x_v)|^2, M_ij =
        // sum_v w_v N_i N_j, solved directly: the weights spread over many
        // orders of magnitude. M is positive definite: a coarse field that
        // vanishes at every fine vertex is zero, since each coarse cell
        // holds a solid voxel, and the 8 vertices of a voxel determine a
        // trilinear field.
        // Summed per coarse cell first: one addition to M per cell and
        // entry, not per fine vertex.
        for (auto &m : local)
          m.fill(0);
        for (unsigned int c = 0; c < 3; ++c)
          b[c] = 0;
        for (std::size_t v = 0; v < samples.size(); ++v)
          {
            const Sample &s = samples[v];
            for (unsigned int i = 0; i < 8; ++i)
              {
                const double wN = weights[v] * s.N[i];
                for (unsigned int c = 0; c < 3; ++c)
                  b[c](cell_vertices[s.cell][i]) += wN * s.f[c];
                for (unsigned int j = 0; j < 8; ++j)
                  local[s.cell][8 * i + j] += wN * s.N[j];
              }
          }
        M = 0;
        for (unsigned int cell = 0; cell < local.size(); ++cell)
          for (unsigned int i = 0; i < 8; ++i)
            for (unsigned int j = 0; j < 8; ++j)
              M.add(cell_vertices[cell][i],
                    cell_vertices[cell][j],
                    local[cell][8 * i + j]);
        AssertThrow(cholesky.factorize(M),
                    ExcMessage("The grid fit's normal equations are not "
                               "positive definite."));
        for (unsigned int c = 0; c < 3; ++c)
          cholesky.vmult(a[c], b[c]);

        // The mean distance, and the bound: with y_v = w_v (A_v a - f_v),
        // sum_v A_v^T y_v = 0 (the normal equations), so for every field
        // a', sum_v |A_v a' - f_v| >= sum_v y_v . (A_v a' - f_v) / max|y| =
        // sum_v w_v r_v^2 / max_v w_v r_v.
        double sum = 0, dual = 0, largest = 0;
        for (std::size_t v = 0; v < samples.size(); ++v)
          {
            r[v] = distance(samples[v]);
            sum += r[v];
            dual += weights[v] * r[v] * r[v];
            largest = std::max(largest, weights[v] * r[v]);
          }
        const double mean = sum / n;
        fit.lower_bound =
          std::max(fit.lower_bound, largest > 0 ? dual / largest / n : mean);
        if (fit.iterations == 1)
          delta = 1e-5 * mean;
        fit.converged =
          mean - fit.lower_bound <= tolerance * mean || mean <= 1e-14 * scale;
        if (fit.converged)
          break;
        for (std::size_t v = 0; v < samples.size(); ++v)
          weights[v] = 1. / std::sqrt(r[v] * r[v] + delta * delta);
      }
    fit.iterations = std::min(fit.iterations, max_iterations);

    // The field in the numbering of the coarse discretization.
    fit.field.reinit(coarse.dof_handler.n_dofs());
    for (const auto &cell : coarse.dof_handler.active_cell_iterators())
      for (const unsigned int w : cell->vertex_indices())
        for (unsigned int c = 0; c < 3; ++c)
          fit.field(cell->vertex_dof_index(w, c)) =
            a[c](cell_vertices[cell->active_cell_index()][w]);
    fit.error = vertex_error(grid, fine, u_fine, coarse, fit.field);
    fit.lower_bound /= fit.error.length;
    return fit;
  }
} // namespace ddfem::report
