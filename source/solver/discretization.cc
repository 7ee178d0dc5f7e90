#include <deal.II/fe/fe_q.h>

#include <ddfem/solver/discretization.h>

namespace ddfem::solver
{
  Discretization::Discretization(const scene::Scene &scene,
                                 const unsigned int  degree)
    : fe(FE_Q<3>(degree), 3)
    , dof_handler(triangulation)
    , quadrature(QGauss<3>(degree + 1))
    , extent(scene.grid.extent())
  {
    cell_blocks = scene::make_voxel_mesh(scene.grid, 0, triangulation);
    dof_handler.distribute_dofs(fe);

    material_points.resize(triangulation.n_active_cells() * quadrature.size());
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        const auto point = scene.palette[cell->material_id()].material_point();
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          material_points[cell->active_cell_index() * quadrature.size() + q] =
            point;
      }
  }
} // namespace ddfem::solver
