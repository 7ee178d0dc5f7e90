#ifndef ddfem_solver_discretization_h
#define ddfem_solver_discretization_h

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/tria.h>

#include <ddfem/material/kernel.h>
#include <ddfem/scene/scene.h>

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace ddfem::solver
{
  using namespace dealii;

  /// The point offset of the 2-point Gauss rule, 1/sqrt(3).
  constexpr double gauss_point_offset = 0.57735026918962576451;

  /**
   * The default of "Discretization/Level-2 point offset". A 4x4x4 block's
   * trilinear element is far stiffer in bending than its 64 voxels; at
   * 0.4 its bending modes keep 0.48 of the Gauss rule's energy, where a
   * bar bent in plane strain at nu = 0.45 has the fine energy
   * (doc/coarsening.md, "The coarse point offset"). On the shipped scenes
   * it lowered ddfem's level-2 error in 9 of 13 states, by up to 11 times
   * (doc/coarsening.md, "Level-2 point offset").
   */
  constexpr double default_level2_point_offset = 0.4;

  /**
   * The point offsets allowed at coarsening level @p level (1 or 2),
   * [first, second). At level 1 from 0.25, below which the hourglass
   * (bending) modes keep less than a fifth of the Gauss rule's energy and
   * the element nears a mechanism, up to 1, where the points reach the
   * faces. At level 2 from 0.37 up to 0.73, rounded in from
   * (sqrt(3) - 1) / 2 = 0.366 and sqrt(3) - 1 = 0.732, beyond which some of
   * the 64 points leave their voxels (coarse_quadrature()).
   */
  inline std::pair<double, double>
  point_offset_range(const unsigned int level)
  {
    return level == 2 ? std::pair(0.37, 0.73) : std::pair(0.25, 1.);
  }

  /// Whether @p point_offset lies in point_offset_range(@p level).
  inline bool
  valid_point_offset(const double point_offset, const unsigned int level)
  {
    const auto [low, high] = point_offset_range(level);
    return point_offset >= low && point_offset < high;
  }

  /**
   * The parameter that sets the point offset of coarsening level @p level:
   * "Discretization/Coarse point offset" at level 1,
   * "Discretization/Level-2 point offset" at level 2.
   */
  std::string
  point_offset_parameter(const unsigned int level);

  /**
   * Throws ExcMessage naming point_offset_parameter(@p level) unless
   * valid_point_offset(@p point_offset, @p level).
   */
  void
  check_point_offset(const double point_offset, const unsigned int level);

  /**
   * The quadrature rule of a coarse element of coarsening level 1 or 2,
   * the points metamaterials are defined at. At level 1 it has 8 points
   * of weight 1/8, point k in child octant k, at +-@p point_offset of the
   * element's half-width from its centre in every direction: the 2-point
   * Gauss rule with the default gauss_point_offset (the paper's element).
   * At level 2 it has 64 points of weight 1/64, one in each voxel of the
   * 4x4x4 block: the 2-point Gauss rule iterated twice (where level-1
   * children of the default offset have their points), moved toward the
   * centre by the factor @p point_offset / gauss_point_offset.
   *
   * At both levels a smaller offset leaves the energy of every
   * constant-strain mode as it is (the weights integrate constants exactly)
   * and scales the energy of the trilinear element's bending modes, whose
   * strains grow linearly away from the centre, by (@p point_offset /
   * gauss_point_offset)^2.
   *
   * Throws ExcMessage for other levels and for offsets outside
   * point_offset_range(@p level) (naming point_offset_parameter(@p level)).
   */
  Quadrature<3>
  coarse_quadrature(const unsigned int level,
                    const double       point_offset = gauss_point_offset);

  /**
   * A continuous finite element discretization of a scene: the voxel mesh
   * (or the mesh of its 2x2x2 or 4x4x4 blocks), an FE_Q(p)^3 element, its
   * degrees of freedom, a quadrature rule and the material record of every
   * quadrature point. The material records are what distinguishes the fine
   * model (each point copies its voxel's palette material) from coarse ones
   * (each point carries a metamaterial's or a baseline's data); everything
   * downstream only sees the records.
   */
  class Discretization
  {
  public:
    /**
     * The discretization of @p scene at coarsening @p level.
     *
     * Level 0 is the fine model: one cell per solid voxel, FE_Q(@p degree)^3,
     * Gauss quadrature with degree+1 points per direction, every quadrature
     * point carrying its voxel's palette material.
     *
     * Levels 1 and 2 are coarse models: one cell per block of 2^level voxels
     * per direction that holds a solid voxel, FE_Q(1)^3 (@p degree must be
     * 1) and coarse_quadrature(level, @p point_offset). Their material
     * records are allocated but left zero: a coarsening::Coarsener fills
     * them.
     */
    Discretization(const scene::Scene &scene,
                   const unsigned int  degree,
                   const unsigned int  level        = 0,
                   const double        point_offset = gauss_point_offset);

    /**
     * The active index of the cell whose voxel or block holds voxel @p v
     * (linear index) of @p grid, the grid this discretization was built
     * from; numbers::invalid_unsigned_int if that block has no cell.
     */
    unsigned int
    cell_of_voxel(const scene::VoxelGrid &grid, const std::size_t v) const;

    /**
     * The fine model only: the voxels @p changed (linear indices, all
     * solid) of @p scene's grid have new materials; their cells' records
     * copy them.
     */
    void
    update_voxel_materials(const scene::Scene             &scene,
                           const std::vector<std::size_t> &changed);

    /**
     * Sets the material id of cell @p cell_index (what output shows) to
     * scene::dominant_material() of its block in @p grid: after a material
     * edit, for the cells whose records changed.
     */
    void
    update_material_id(const scene::VoxelGrid &grid,
                       const unsigned int      cell_index);

    /// The material record of quadrature point @p q of the cell with
    /// active index @p cell_index.
    const material::MaterialPoint &
    material(const unsigned int cell_index, const unsigned int q) const
    {
      return material_points[std::size_t(cell_index) * quadrature.size() + q];
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
    /// Coarsening level: 0 for the fine mesh, 1 or 2 for blocks of 2^level
    /// voxels per direction.
    unsigned int level;
    /// Lexicographic voxel (level 0) or block index of each active cell.
    std::vector<std::size_t> cell_blocks;
    /**
     * The solid voxels of each active cell's block, a bit per voxel: voxel
     * (i, j, k) of the block, each from 0 to 2^level - 1, is bit
     * i + w (j + w k) with w = 2^level (at level 0 the single bit 0). Loads
     * act on the fine solid these bits describe, at every level.
     */
    std::vector<std::uint64_t> solid_voxels;
    /// The voxels along each axis of the grid the mesh was made from.
    std::array<unsigned int, 3> grid_size;
    /// The bounding box size of the voxel grid (m).
    Point<3> extent;

  private:
    /// Gives every point of the fine cell @p c its voxel's palette material.
    void
    copy_voxel_material(const scene::Scene &scene, const std::size_t c);
  };
} // namespace ddfem::solver

#endif
