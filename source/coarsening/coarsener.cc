#include <ddfem/base/parsing.h>
#include <ddfem/coarsening/coarsener.h>

#include <algorithm>
#include <set>

namespace ddfem::coarsening
{
  std::string
  to_string(const CoarseningMethod method)
  {
    switch (method)
      {
        case CoarseningMethod::ddfem:
          return "ddfem";
        case CoarseningMethod::naive:
          return "naive";
        case CoarseningMethod::average:
          return "average";
      }
    return "";
  }



  CoarseningMethod
  coarsening_method(const std::string &name)
  {
    for (const auto m : {CoarseningMethod::ddfem,
                         CoarseningMethod::naive,
                         CoarseningMethod::average})
      if (to_string(m) == name)
        return m;
    AssertThrow(false,
                ExcMessage("Unknown coarsening method '" + name +
                           "'; allowed are ddfem, naive, average."));
    return CoarseningMethod::ddfem;
  }



  Coarsener::Coarsener(const CoarseningMethod method,
                       const unsigned int     level,
                       const scene::Palette  &palette,
                       const double           point_offset,
                       const Database        *level1,
                       const Hierarchy       *level2)
    : coarsening(method)
    , coarsening_level(level)
    , offset(point_offset)
    , palette(palette)
    , level1(level1)
    , level2(level2)
    , quadrature(solver::coarse_quadrature(level, point_offset))
  {
    AssertThrow(method != CoarseningMethod::ddfem ||
                  (level1 != nullptr &&
                   (level == 1 || (level2 != nullptr && !level2->empty()))),
                ExcMessage("The ddfem coarsener needs the database."));
    if (method == CoarseningMethod::ddfem)
      {
        const double fitted =
          level == 1 ? level1->point_offset() : level2->settings.point_offset;
        AssertThrow(fitted == point_offset,
                    ExcMessage("The metamaterial database's level " +
                               std::to_string(level) +
                               " was fitted for the point offset " +
                               Utilities::to_string(fitted) + ", not for " +
                               solver::point_offset_parameter(level) + " = " +
                               Utilities::to_string(point_offset) + "."));
      }
    const unsigned int n = 1u << level;
    for (const Point<3> &x : quadrature.get_points())
      point_voxel.push_back({{static_cast<unsigned int>(x[0] * n),
                              static_cast<unsigned int>(x[1] * n),
                              static_cast<unsigned int>(x[2] * n)}});
  }



  Combination
  Coarsener::combination(const scene::VoxelGrid &grid,
                         const unsigned int      i,
                         const unsigned int      j,
                         const unsigned int      k)
  {
    Combination c;
    for (unsigned int child = 0; child < 8; ++child)
      c[child] =
        grid(i + (child & 1), j + ((child >> 1) & 1), k + ((child >> 2) & 1));
    return c;
  }



  std::array<Combination, 8>
  Coarsener::sub_blocks(const scene::VoxelGrid &grid,
                        const unsigned int      i,
                        const unsigned int      j,
                        const unsigned int      k)
  {
    std::array<Combination, 8> blocks;
    for (unsigned int b = 0; b < 8; ++b)
      blocks[b] = combination(grid,
                              i + 2 * (b & 1),
                              j + 2 * ((b >> 1) & 1),
                              k + 2 * ((b >> 2) & 1));
    return blocks;
  }



  Metamaterial
  Coarsener::block_material(const scene::VoxelGrid &grid,
                            const std::size_t       block) const
  {
    const auto [i, j, k] = scene::block_origin(grid, block, coarsening_level);

    if (coarsening == CoarseningMethod::ddfem)
      return coarsening_level == 1 ?
               level1->lookup(combination(grid, i, j, k)) :
               level2->lookup(*level1, sub_blocks(grid, i, j, k));

    // The baselines: the palette materials of the block's voxels.
    Metamaterial result;
    result.points.resize(point_voxel.size());
    for (unsigned int q = 0; q < point_voxel.size(); ++q)
      {
        const auto &o = point_voxel[q];
        if (const auto id = grid(i + o[0], j + o[1], k + o[2]);
            id != scene::void_id)
          result.points[q] = palette[id].material_point();
      }
    // Palette materials have mu > 0, so the points with mu = 0 are void.
    if (coarsening == CoarseningMethod::naive)
      {
        const double floor = result.stiffness_floor(void_stiffness);
        for (auto &p : result.points)
          if (p.mu == 0)
            p.mu = floor;
      }
    else
      {
        material::MaterialPoint mean;
        for (const auto &p : result.points)
          {
            mean.mu += p.mu / result.points.size();
            mean.lambda += p.lambda / result.points.size();
          }
        std::fill(result.points.begin(), result.points.end(), mean);
      }
    return result;
  }



  void
  Coarsener::coarsen(const scene::VoxelGrid &grid,
                     solver::Discretization &coarse) const
  {
    check_model(grid, coarse);
    for (unsigned int c = 0; c < coarse.cell_blocks.size(); ++c)
      assign_cell(grid, c, coarse);
  }



  unsigned int
  Coarsener::recoarsen(const scene::VoxelGrid         &grid,
                       const std::vector<std::size_t> &changed,
                       solver::Discretization         &coarse) const
  {
    check_model(grid, coarse);
    std::set<unsigned int> cells;
    for (const std::size_t v : changed)
      {
        const unsigned int cell = coarse.cell_of_voxel(grid, v);
        AssertThrow(cell != numbers::invalid_unsigned_int,
                    ExcMessage("A material edit touched a block without "
                               "solid voxels; edits may only change the "
                               "material of solid voxels."));
        cells.insert(cell);
      }
    // The mesh set the material ids of the layout it was made from; an edit
    // may change which material a block has most of.
    for (const unsigned int cell : cells)
      {
        assign_cell(grid, cell, coarse);
        coarse.update_material_id(grid, cell);
      }
    return cells.size();
  }



  void
  Coarsener::check_model(const scene::VoxelGrid       &grid,
                         const solver::Discretization &coarse) const
  {
    AssertThrow(coarse.level == coarsening_level,
                ExcMessage("A coarsener of level " +
                           std::to_string(coarsening_level) +
                           " was given a model of level " +
                           std::to_string(coarse.level) + "."));
    AssertThrow(grid.size() == coarse.grid_size &&
                  grid.extent().distance(coarse.extent) <=
                    1e-12 * grid.extent().norm(),
                ExcMessage("The coarse model was built from another voxel "
                           "grid than the one given to the coarsener."));
    bool same_points = coarse.quadrature.size() == quadrature.size();
    for (unsigned int q = 0; same_points && q < quadrature.size(); ++q)
      same_points =
        coarse.quadrature.point(q).distance(quadrature.point(q)) < 1e-12;
    AssertThrow(same_points,
                ExcMessage("The coarse model's quadrature points are not "
                           "those of " +
                           solver::point_offset_parameter(coarsening_level) +
                           " = " + format_number(offset, 6) +
                           ", which the coarsener fills records for."));
  }



  void
  Coarsener::assign_cell(const scene::VoxelGrid &grid,
                         const unsigned int      cell,
                         solver::Discretization &coarse) const
  {
    const Metamaterial m = block_material(grid, coarse.cell_blocks[cell]);
    AssertDimension(m.points.size(), coarse.quadrature.size());
    std::copy(m.points.begin(),
              m.points.end(),
              coarse.material_points.begin() +
                std::size_t(cell) * coarse.quadrature.size());
  }
} // namespace ddfem::coarsening
