#include <deal.II/fe/fe_q.h>

#include <ddfem/base/parsing.h>
#include <ddfem/solver/discretization.h>

#include <algorithm>

namespace ddfem::solver
{
  std::string
  point_offset_parameter(const unsigned int level)
  {
    return level == 2 ? "Discretization/Level-2 point offset" :
                        "Discretization/Coarse point offset";
  }



  void
  check_point_offset(const double point_offset, const unsigned int level)
  {
    const auto [low, high] = point_offset_range(level);
    AssertThrow(valid_point_offset(point_offset, level),
                ExcMessage(
                  point_offset_parameter(level) + " must lie from " +
                  format_number(low) + " up to (not including) " +
                  format_number(high) + ", not " + format_number(point_offset) +
                  (level == 2 ?
                     ": the range is rounded in from (sqrt(3) - 1) / 2 = "
                     "0.366 and sqrt(3) - 1 = 0.732, beyond which some of "
                     "the 64 points leave their voxels." :
                     ". Below " + format_number(low) +
                       " the element nears a mechanism (its bending energy "
                       "scales with the offset squared); at 1 its points "
                       "reach the cell's faces.")));
  }



  Quadrature<3>
  coarse_quadrature(const unsigned int level, const double point_offset)
  {
    AssertThrow(level == 1 || level == 2,
                ExcMessage("Coarsening levels must be 1 or 2, not " +
                           std::to_string(level) + "."));
    check_point_offset(point_offset, level);
    // The Gauss points (iterated at level 2) moved toward the centre by the
    // factor (exactly the Gauss rule for the default offset).
    const Quadrature<1> gauss =
      level == 1 ? Quadrature<1>(QGauss<1>(2)) : QIterated<1>(QGauss<1>(2), 2);
    const double          factor = point_offset / gauss_point_offset;
    std::vector<Point<1>> points;
    for (const Point<1> &x : gauss.get_points())
      points.emplace_back(x[0] * factor + 0.5 * (1 - factor));
    return Quadrature<3>(Quadrature<1>(points, gauss.get_weights()));
  }



  Discretization::Discretization(const scene::Scene &scene,
                                 const unsigned int  degree,
                                 const unsigned int  level,
                                 const double        point_offset)
    : fe(FE_Q<3>(degree), 3)
    , dof_handler(triangulation)
    , quadrature(level == 0 ? Quadrature<3>(QGauss<3>(degree + 1)) :
                              coarse_quadrature(level, point_offset))
    , level(level)
    , grid_size(scene.grid.size())
    , extent(scene.grid.extent())
  {
    AssertThrow(level == 0 || degree == 1,
                ExcMessage("Coarse elements are trilinear: "
                           "Discretization/Polynomial degree must be 1 for "
                           "Method = ddfem, naive or average, not " +
                           std::to_string(degree) + "."));
    cell_blocks = scene::make_voxel_mesh(scene.grid, level, triangulation);
    dof_handler.distribute_dofs(fe);

    const unsigned int width = 1u << level;
    solid_voxels.resize(cell_blocks.size());
    for (std::size_t c = 0; c < cell_blocks.size(); ++c)
      {
        const auto o = scene::block_origin(scene.grid, cell_blocks[c], level);
        for (unsigned int k = 0; k < width; ++k)
          for (unsigned int j = 0; j < width; ++j)
            for (unsigned int i = 0; i < width; ++i)
              if (scene.grid(o[0] + i, o[1] + j, o[2] + k) != scene::void_id)
                solid_voxels[c] |= std::uint64_t(1)
                                   << (i + width * (j + width * k));
      }

    material_points.resize(std::size_t(triangulation.n_active_cells()) *
                           quadrature.size());
    if (level == 0)
      for (std::size_t c = 0; c < cell_blocks.size(); ++c)
        copy_voxel_material(scene, c);
  }



  void
  Discretization::copy_voxel_material(const scene::Scene &scene,
                                      const std::size_t   c)
  {
    const auto point =
      scene.palette[scene.grid[cell_blocks[c]]].material_point();
    std::fill(material_points.begin() + c * quadrature.size(),
              material_points.begin() + (c + 1) * quadrature.size(),
              point);
  }



  unsigned int
  Discretization::cell_of_voxel(const scene::VoxelGrid &grid,
                                const std::size_t       v) const
  {
    // Cells are numbered in increasing block order.
    const unsigned int width = 1u << level;
    const auto        &n     = grid.size();
    const auto         ijk   = grid.coordinates(v);
    const std::size_t  block =
      ijk[0] / width +
      n[0] / width *
        (ijk[1] / width + std::size_t(n[1] / width) * (ijk[2] / width));
    const auto cell =
      std::lower_bound(cell_blocks.begin(), cell_blocks.end(), block);
    return (cell != cell_blocks.end() && *cell == block) ?
             cell - cell_blocks.begin() :
             numbers::invalid_unsigned_int;
  }



  void
  Discretization::update_voxel_materials(
    const scene::Scene             &scene,
    const std::vector<std::size_t> &changed)
  {
    // Checked in Release too: a voxel without a cell would be written far
    // outside the material points (edits keep the solid voxels; Layout).
    AssertThrow(level == 0,
                ExcMessage("Coarse models are updated by a Coarsener."));
    for (const std::size_t v : changed)
      {
        const unsigned int cell = cell_of_voxel(scene.grid, v);
        AssertThrow(cell != numbers::invalid_unsigned_int,
                    ExcMessage("A material edit changed a void voxel, which "
                               "the fine model has no cell for."));
        copy_voxel_material(scene, cell);
        update_material_id(scene.grid, cell);
      }
  }



  void
  Discretization::update_material_id(const scene::VoxelGrid &grid,
                                     const unsigned int      cell_index)
  {
    // The mesh is not refined: active cell c is cell c of level 0.
    const typename Triangulation<3>::active_cell_iterator cell(&triangulation,
                                                               0,
                                                               cell_index);
    cell->set_material_id(
      scene::dominant_material(grid, cell_blocks[cell_index], level));
  }
} // namespace ddfem::solver
