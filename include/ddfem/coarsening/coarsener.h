#ifndef ddfem_coarsening_coarsener_h
#define ddfem_coarsening_coarsener_h

#include <ddfem/coarsening/database.h>
#include <ddfem/coarsening/hierarchy.h>
#include <ddfem/coarsening/metamaterial.h>
#include <ddfem/scene/palette.h>
#include <ddfem/scene/voxel_grid.h>
#include <ddfem/solver/discretization.h>

#include <array>
#include <string>
#include <vector>

namespace ddfem::coarsening
{
  /// How a coarse element gets the material of its block of voxels.
  enum class CoarseningMethod
  {
    /// The block's fitted metamaterial from the database (paper section 5).
    ddfem,
    /// Each quadrature point copies the palette material of the voxel it
    /// lies in, unfitted (the paper's naive baseline).
    naive,
    /// Every quadrature point gets the volume average of the block's mu and
    /// lambda (void counts as zero).
    average
  };

  /// "ddfem", "naive" or "average".
  std::string
  to_string(const CoarseningMethod method);

  /// The method named @p name (one of to_string()'s values).
  CoarseningMethod
  coarsening_method(const std::string &name);

  /**
   * Online coarsening (paper section 5): fills the material records of a
   * coarse Discretization (level 1 or 2) from the material ids of the
   * voxel blocks its cells stand for. With CoarseningMethod::ddfem a block
   * is looked up in the metamaterial database (level 1: its 2x2x2
   * combination; level 2: its eight 2x2x2 sub-blocks through the level-2
   * tables); the baselines need no database.
   *
   * A void voxel's quadrature point in the naive element gets a shear
   * modulus of void_stiffness times the block's stiffest mu, but no more
   * than its softest (Metamaterial::stiffness_floor(), the fitter's
   * default stiffness floor), and no lambda: with zero stiffness a mostly
   * void element would have zero-energy hourglass modes.
   */
  class Coarsener
  {
  public:
    /**
     * A coarsener for coarsening @p level (1 or 2) of coarse elements with
     * the point offset @p point_offset (solver::coarse_quadrature()). With
     * CoarseningMethod::ddfem, @p level1 is required, and @p level2 too at
     * level 2, the one of @p level fitted for that offset; both must
     * outlive the coarsener.
     */
    Coarsener(const CoarseningMethod method,
              const unsigned int     level,
              const scene::Palette  &palette,
              const double           point_offset,
              const Database        *level1 = nullptr,
              const Hierarchy       *level2 = nullptr);

    /// The coarsening level.
    unsigned int
    level() const
    {
      return coarsening_level;
    }

    /// The coarse element's point offset (solver::coarse_quadrature()).
    double
    point_offset() const
    {
      return offset;
    }

    /**
     * Fills the material record of every quadrature point of @p coarse
     * (built from @p grid at level() and point_offset(); the cells'
     * material ids are the ones the mesh was made with). Throws
     * ExcMessage if @p coarse has another level or other points.
     */
    void
    coarsen(const scene::VoxelGrid &grid, solver::Discretization &coarse) const;

    /**
     * After material edits of the voxels @p changed (linear voxel indices)
     * that left the solid unchanged: refills only the cells whose block
     * holds a changed voxel, and sets their material ids (what output
     * shows) anew. Returns their number.
     */
    unsigned int
    recoarsen(const scene::VoxelGrid         &grid,
              const std::vector<std::size_t> &changed,
              solver::Discretization         &coarse) const;

    /**
     * The material of the block with lexicographic index @p block in the
     * grid coarsened level() times: one record per point of
     * coarse_quadrature(level()).
     */
    Metamaterial
    block_material(const scene::VoxelGrid &grid, const std::size_t block) const;

    /**
     * The material ids of the 2x2x2 block whose lowest voxel is (@p i,
     * @p j, @p k), child k = octant (k & 1, (k >> 1) & 1, (k >> 2) & 1).
     */
    static Combination
    combination(const scene::VoxelGrid &grid,
                const unsigned int      i,
                const unsigned int      j,
                const unsigned int      k);

    /**
     * The eight 2x2x2 sub-blocks (in octant order) of the 4x4x4 block whose
     * lowest voxel is (@p i, @p j, @p k).
     */
    static std::array<Combination, 8>
    sub_blocks(const scene::VoxelGrid &grid,
               const unsigned int      i,
               const unsigned int      j,
               const unsigned int      k);

    /// The naive element's void stiffness, relative to the block's
    /// largest mu (Metamaterial::stiffness_floor()).
    static constexpr double void_stiffness = default_stiffness_floor;

  private:
    /// Throws ExcMessage unless @p coarse is of level(), has the
    /// quadrature points of point_offset() (the records are per point) and
    /// was built from a grid of the size of @p grid, whose blocks its cells
    /// look up.
    void
    check_model(const scene::VoxelGrid       &grid,
                const solver::Discretization &coarse) const;

    /// Copies block_material() of coarse cell @p cell's block into
    /// @p coarse's records of that cell.
    void
    assign_cell(const scene::VoxelGrid &grid,
                const unsigned int      cell,
                solver::Discretization &coarse) const;

    const CoarseningMethod coarsening;
    const unsigned int     coarsening_level;
    const double           offset;
    const scene::Palette  &palette;
    const Database        *level1;
    const Hierarchy       *level2;
    /// The quadrature rule of level() and point_offset().
    const Quadrature<3> quadrature;
    /// Per quadrature point, the offset of its voxel in the block.
    std::vector<std::array<unsigned int, 3>> point_voxel;
  };
} // namespace ddfem::coarsening

#endif
