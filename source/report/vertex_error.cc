#include <ddfem/report/vertex_error.h>

#include <algorithm>

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



  VertexError
  vertex_error(const scene::VoxelGrid       &grid,
               const solver::Discretization &fine,
               const Vector<double>         &u_fine,
               const solver::Discretization &coarse,
               const Vector<double>         &u_coarse)
  {
    AssertThrow(fine.level == 0 && coarse.fe.degree == 1,
                ExcMessage("The vertex error compares a coarse trilinear "
                           "solution with a fine one."));
    const std::vector<Tensor<1, 3>> fine_u = vertex_displacements(fine, u_fine);
    std::vector<typename DoFHandler<3>::active_cell_iterator> coarse_cells;
    for (const auto &cell : coarse.dof_handler.active_cell_iterators())
      coarse_cells.push_back(cell);

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

    // Each fine vertex once, through the first fine cell that has it; the
    // coarse field is continuous, so any coarse cell holding it will do:
    // the one of that fine cell's block.
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
            Point<3> xi;
            for (unsigned int d = 0; d < 3; ++d)
              xi[d] = (cell->vertex(v)[d] - origin[d]) / size[d];
            Tensor<1, 3> u;
            for (const unsigned int w : coarse_cell->vertex_indices())
              {
                double N = 1;
                for (unsigned int d = 0; d < 3; ++d)
                  N *= (w & (1u << d)) ? xi[d] : 1. - xi[d];
                for (unsigned int c = 0; c < 3; ++c)
                  u[c] += N * u_coarse(coarse_cell->vertex_dof_index(w, c));
              }
            const double e = (u - fine_u[index]).norm() / error.length;
            error.mean += e;
            error.max = std::max(error.max, e);
            ++error.n_vertices;
          }
      }
    error.mean /= std::max<std::size_t>(1, error.n_vertices);
    return error;
  }
} // namespace ddfem::report
