#include <deal.II/dofs/dof_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/sparse_matrix.h>

#include <ddfem/report/vertex_error.h>

#include <algorithm>
#include <array>

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
      AssertThrow(fine.level == 0 && coarse.fe.degree == 1,
                  ExcMessage("The vertex error compares a coarse trilinear "
                             "solution with a fine one."));
      std::vector<typename DoFHandler<3>::active_cell_iterator> coarse_cells;
      for (const auto &cell : coarse.dof_handler.active_cell_iterators())
        coarse_cells.push_back(cell);

      std::vector<bool> done(fine.triangulation.n_vertices(), false);
      for (const auto &cell : fine.triangulation.active_cell_iterators())
        {
          const unsigned int c =
            coarse.cell_of_voxel(grid,
                                 fine.cell_blocks[cell->active_cell_index()]);
          Assert(c != numbers::invalid_unsigned_int, ExcInternalError());
          const auto        &coarse_cell = coarse_cells[c];
          const Point<3>     origin      = coarse_cell->vertex(0);
          const Tensor<1, 3> size        = coarse_cell->vertex(7) - origin;

          for (const unsigned int v : cell->vertex_indices())
            {
              const unsigned int index = cell->vertex_index(v);
              if (done[index])
                continue;
              done[index] = true;
              std::array<double, 8> N;
              for (const unsigned int w : coarse_cell->vertex_indices())
                {
                  N[w] = 1;
                  for (unsigned int d = 0; d < 3; ++d)
                    {
                      const double xi =
                        (cell->vertex(v)[d] - origin[d]) / size[d];
                      N[w] *= (w & (1u << d)) ? xi : 1. - xi;
                    }
                }
              f(index, coarse_cell, N);
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
        Tensor<1, 3> u;
        for (const unsigned int w : coarse_cell->vertex_indices())
          for (unsigned int c = 0; c < 3; ++c)
            u[c] += N[w] * u_coarse(coarse_cell->vertex_dof_index(w, c));
        const double e = (u - fine_u[index]).norm() / error.length;
        error.mean += e;
        error.max = std::max(error.max, e);
        ++error.n_vertices;
      });
    error.mean /= std::max<std::size_t>(1, error.n_vertices);
    return error;
  }



  Vector<double>
  coarse_fit(const scene::VoxelGrid       &grid,
             const solver::Discretization &fine,
             const Vector<double>         &u_fine,
             const solver::Discretization &coarse)
  {
    const std::vector<Tensor<1, 3>> fine_u = vertex_displacements(fine, u_fine);

    // The normal equations M a = b of min sum_v |sum_i a_i N_i(x_v) -
    // u_fine(x_v)|^2 over the coarse nodal values a: M_ij = sum_v N_i N_j
    // for two degrees of freedom of the same component.
    DynamicSparsityPattern dsp(coarse.dof_handler.n_dofs());
    DoFTools::make_sparsity_pattern(coarse.dof_handler, dsp);
    SparsityPattern pattern;
    pattern.copy_from(dsp);
    SparseMatrix<double> M(pattern);
    Vector<double>       b(coarse.dof_handler.n_dofs());
    for_each_fine_vertex(
      grid,
      fine,
      coarse,
      [&](const unsigned int           index,
          const auto                  &coarse_cell,
          const std::array<double, 8> &N) {
        for (const unsigned int i : coarse_cell->vertex_indices())
          for (unsigned int c = 0; c < 3; ++c)
            {
              const types::global_dof_index row =
                coarse_cell->vertex_dof_index(i, c);
              b(row) += N[i] * fine_u[index][c];
              for (const unsigned int j : coarse_cell->vertex_indices())
                M.add(row, coarse_cell->vertex_dof_index(j, c), N[i] * N[j]);
            }
      });

    // M is positive definite: a coarse field that vanishes at every fine
    // vertex is zero, since each coarse cell holds a solid voxel, and the
    // 8 vertices of a voxel determine a trilinear field.
    Vector<double> a(b.size());
    SolverControl  control(1000, 1e-13 * std::max(b.l2_norm(), 1e-300));
    SolverCG<Vector<double>>                 cg(control);
    PreconditionJacobi<SparseMatrix<double>> jacobi;
    jacobi.initialize(M);
    cg.solve(M, a, b, jacobi);
    return a;
  }
} // namespace ddfem::report
