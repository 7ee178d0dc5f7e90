#ifndef ddfem_scene_scene_h
#define ddfem_scene_scene_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/grid/tria.h>

#include <ddfem/scene/boundary_conditions.h>
#include <ddfem/scene/layout.h>
#include <ddfem/scene/palette.h>
#include <ddfem/scene/voxel_grid.h>

#include <array>
#include <vector>

namespace ddfem::scene
{
  using namespace dealii;

  /**
   * Everything a parameter file says about the object being simulated:
   * the voxel grid's size, the palette, the material layout, boundary
   * conditions, loads and probe points. Independent of the discretization
   * method.
   */
  class Scene
  {
  public:
    /// Declares "Geometry", "Materials", "Layout", "Boundary conditions",
    /// "Loads" and the probe list.
    static void
    declare_parameters(ParameterHandler &prm);

    /// Reads and validates all of the above, then fills the voxel grid.
    void
    parse_parameters(ParameterHandler &prm);

    /// Number of material edits in 'Layout/Edits'.
    unsigned int
    n_edits() const
    {
      return edit_changes.size();
    }

    /**
     * Applies material edit @p e (from 0) to the grid; returns the linear
     * indices of the changed voxels (see Layout::apply_edit()). Edits are
     * applied in turn, from the grid as laid out: edit @p e gives the
     * voxels it changes the ids it gave them after edits 0 to @p e - 1.
     */
    std::vector<std::size_t>
    apply_edit(const unsigned int e);

    /**
     * The grids of every state of the scene: as laid out, then after each
     * material edit in turn (the grid itself is not changed).
     */
    std::vector<VoxelGrid>
    states() const;

    /// The voxel grid with one material id per voxel.
    VoxelGrid grid;
    /// The materials voxel ids refer to.
    Palette palette;
    /// Boundary conditions and loads.
    BoundaryConditions boundary_conditions;
    /// Points (m) whose displacement is reported.
    std::vector<Point<3>> probes;

  private:
    Layout layout;
    /// The grid as laid out, before any edit (empty without edits).
    VoxelGrid laid_out;
    /// Per material edit, found once when the scene is read: the voxels
    /// it changes and their new material ids.
    std::vector<std::vector<std::pair<std::size_t, MaterialId>>> edit_changes;
  };

  /// How far, in voxel sizes, a probe point may lie off the solid's
  /// surface: round-off in a point given on the surface.
  constexpr double probe_tolerance = 1e-9;

  /**
   * The error that the probe point @p p (m) lies outside the solid, naming
   * Geometry/Probe points (12 digits: a point just outside must not read
   * like one on the boundary).
   */
  ExcMessage
  probe_outside(const Point<3> &p);

  /**
   * Throws ExcMessage, naming Geometry/Grid size, unless every size of
   * @p grid is divisible by 2^@p level, the block size of coarsening level
   * @p level.
   */
  void
  check_coarsenable(const VoxelGrid &grid, const unsigned int level);

  /**
   * The first voxel (i, j, k) of block @p block (lexicographic index in the
   * grid coarsened @p level times, as make_voxel_mesh() returns it) of
   * @p grid: the block holds the voxels from there on, 2^@p level along
   * each axis.
   */
  std::array<unsigned int, 3>
  block_origin(const VoxelGrid   &grid,
               const std::size_t  block,
               const unsigned int level);

  /**
   * The material id a cell of block @p block (as in block_origin()) shows
   * in output: at level 0 the voxel's id, above it the id most of the
   * block's solid voxels have (the smallest of those that tie). Coarse
   * elements carry per-point metamaterials; this only labels them.
   */
  types::material_id
  dominant_material(const VoxelGrid   &grid,
                    const std::size_t  block,
                    const unsigned int level);

  /**
   * Builds the hexahedral mesh of a voxel grid coarsened @p level times:
   * cells are the 2^level x 2^level x 2^level blocks of voxels that contain
   * at least one solid voxel (level 0: the solid voxels themselves). Void
   * blocks get no cell, hence no degrees of freedom. The grid size must be
   * divisible by 2^level.
   *
   * Returns, for each active cell in the order of active_cell_index(), the
   * lexicographic index of its block in the coarsened grid. The cell's
   * material id is dominant_material() of its block.
   *
   * Throws ExcMessage naming Geometry/Grid size, before the mesh is built,
   * if it would have more cells than models of at least 8 KiB per cell
   * can hold in the machine's physical memory (a run would end in the
   * kernel's out-of-memory killer without a message).
   */
  std::vector<std::size_t>
  make_voxel_mesh(const VoxelGrid   &grid,
                  const unsigned int level,
                  Triangulation<3>  &tria);
} // namespace ddfem::scene

#endif
