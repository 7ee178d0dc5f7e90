#ifndef ddfem_solver_discretization_h
#define ddfem_solver_discretization_h

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/tria.h>

#include <ddfem/material/kernel.h>
#include <ddfem/scene/scene.h>

#include <memory>
#include <vector>

namespace ddfem::solver
{
  using namespace dealii;

  /**
   * A continuous finite element discretization of a scene: the voxel mesh,
   * an FE_Q(p)^3 element, its degrees of freedom, a quadrature rule and the
   * material record of every quadrature point. The material records are
   * what distinguishes the fine model (each point copies its voxel's
   * palette material) from coarse ones (each point carries fitted data);
   * everything downstream only sees the records.
   */
  class Discretization
  {
  public:
    /**
     * The fine discretization: one cell per solid voxel, FE_Q(@p degree)^3,
     * Gauss quadrature with degree+1 points per direction, every
     * quadrature point carrying its voxel's palette material.
     */
    Discretization(const scene::Scene &scene, const unsigned int degree);

    /// The material record of quadrature point @p q of the cell with
    /// active index @p cell_index.
    const material::MaterialPoint &
    material(const unsigned int cell_index, const unsigned int q) const
    {
      return material_points[cell_index * quadrature.size() + q];
    }

    /// The mesh of the solid voxels (or blocks).
    Triangulation<3> triangulation;
    /// The vector-valued FE_Q(p)^3 element.
    FESystem<3> fe;
    /// Degrees of freedom on the mesh.
    DoFHandler<3> dof_handler;
    /// The cell quadrature rule.
    Quadrature<3> quadrature;
    /// The (affine) mapping of the hexahedral cells.
    MappingQ1<3> mapping;
    /// Material record per cell and quadrature point, cell-major.
    std::vector<material::MaterialPoint> material_points;
    /// Lexicographic voxel (block) index of each active cell.
    std::vector<std::size_t> cell_blocks;
    /// The bounding box size of the voxel grid (m).
    Point<3> extent;
  };
} // namespace ddfem::solver

#endif
