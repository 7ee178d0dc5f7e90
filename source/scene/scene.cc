#include <deal.II/base/utilities.h>
#include <deal.II/grid/tria_description.h>

#include <ddfem/base/memory.h>
#include <ddfem/base/parsing.h>
#include <ddfem/scene/scene.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace ddfem::scene
{
  namespace
  {
    /**
     * Memory (bytes) any model needs at least per cell of its mesh: less
     * than half of the about 20 KiB per cell measured for fine models
     * (peak memory of bar-32 and fibers in doc/benchmarks.md).
     */
    constexpr std::size_t minimum_bytes_per_cell = 8192;

    /// The number of cells whose models could fit in physical memory (no
    /// limit if the system does not say how much it has).
    std::size_t
    cells_that_fit_in_memory()
    {
      const double memory = physical_memory();
      return memory > 0 ? memory / minimum_bytes_per_cell :
                          std::numeric_limits<std::size_t>::max();
    }

    /**
     * Throws ExcMessage naming @p p unless it lies in a solid voxel of
     * @p grid or on its surface (within probe_tolerance voxel sizes), so
     * that every model, fine or coarse, measures the same material point.
     */
    void
    check_probe(const VoxelGrid &grid, const Point<3> &p)
    {
      const double        h = grid.voxel_size();
      std::array<long, 3> lower, upper;
      for (unsigned int d = 0; d < 3; ++d)
        {
          lower[d] =
            std::max(0L, std::lround(std::floor(p[d] / h - probe_tolerance)));
          upper[d] =
            std::min(long(grid.size()[d]) - 1,
                     std::lround(std::floor(p[d] / h + probe_tolerance)));
        }
      bool solid = false;
      for (long k = lower[2]; k <= upper[2]; ++k)
        for (long j = lower[1]; j <= upper[1]; ++j)
          for (long i = lower[0]; i <= upper[0]; ++i)
            solid = solid || grid(i, j, k) != void_id;
      AssertThrow(solid, probe_outside(p));
    }



    /// The error of a scene whose @p grid has no solid voxel.
    ExcMessage
    no_solid_voxel(const VoxelGrid &grid)
    {
      const auto &n = grid.size();
      return ExcMessage("The scene has no solid voxel: every voxel of the " +
                        std::to_string(n[0]) + "x" + std::to_string(n[1]) +
                        "x" + std::to_string(n[2]) +
                        " grid is void (check Layout).");
    }
  } // namespace



  void
  Scene::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Geometry");
    prm.declare_entry("Grid size",
                      "16, 16, 16",
                      Patterns::List(Patterns::Integer(1), 3, 3),
                      "Number of voxels nx, ny, nz along x, y, z.");
    // Any number: parse_parameters() checks the range and names it.
    prm.declare_entry("Voxel size",
                      "0.01",
                      Patterns::Double(),
                      "Edge length of a voxel (m), from 1e-6 to 1e3.");
    prm.declare_entry(
      "Probe points",
      "",
      Patterns::Anything(),
      "Points 'x, y, z' (m, reference configuration) separated by ';' "
      "whose displacement is printed and written to summary.json.");
    prm.leave_subsection();

    Palette::declare_parameters(prm);
    Layout::declare_parameters(prm);
    BoundaryConditions::declare_parameters(prm);
  }



  void
  Scene::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Geometry");
    const auto n = Utilities::string_to_int(
      split_list(prm.get("Grid size"), ',', "Geometry/Grid size"));
    const double h = prm.get_double("Voxel size");
    AssertThrow(h >= 1e-6 && h <= 1e3,
                ExcMessage("Geometry/Voxel size = " + prm.get("Voxel size") +
                           ": expected a value from 1e-6 to 1e3 (m)."));
    AssertThrow(static_cast<double>(n[0]) * n[1] * n[2] <= 2e8,
                ExcMessage(
                  "Geometry/Grid size: at most 2e8 voxels are supported."));
    grid = VoxelGrid({{static_cast<unsigned int>(n[0]),
                       static_cast<unsigned int>(n[1]),
                       static_cast<unsigned int>(n[2])}},
                     h);
    probes.clear();
    for (const std::string &p :
         split_list(prm.get("Probe points"), ';', "Geometry/Probe points"))
      {
        probes.push_back(
          parse_point(split_list(p, ',', "Geometry/Probe points"),
                      "Geometry/Probe points, \"" + p + "\""));
      }
    prm.leave_subsection();

    palette.parse_parameters(prm);
    layout.parse_parameters(prm, palette.size());
    boundary_conditions.parse_parameters(prm, grid.extent(), h);
    layout.fill(grid);
    AssertThrow(grid.n_solid_voxels() > 0, no_solid_voxel(grid));
    for (const Point<3> &p : probes)
      check_probe(grid, p);
    // Every edit is checked and its changes recorded now, before anything
    // is solved or written. Edits keep the solid's voxels, so the probes
    // stay in the solid.
    edit_changes.clear();
    laid_out = layout.n_edits() > 0 ? grid : VoxelGrid();
    VoxelGrid edited = grid;
    for (unsigned int e = 0; e < layout.n_edits(); ++e)
      {
        edit_changes.emplace_back();
        for (const std::size_t v : layout.apply_edit(e, edited))
          edit_changes.back().emplace_back(v, edited[v]);
      }
  }



  std::vector<std::size_t>
  Scene::apply_edit(const unsigned int e)
  {
    AssertIndexRange(e, n_edits());
    std::vector<std::size_t> changed;
    changed.reserve(edit_changes[e].size());
    for (const auto &[v, id] : edit_changes[e])
      {
        grid[v] = id;
        changed.push_back(v);
      }
    return changed;
  }



  std::vector<VoxelGrid>
  Scene::states() const
  {
    std::vector<VoxelGrid> result = {n_edits() > 0 ? laid_out : grid};
    for (const auto &changes : edit_changes)
      {
        result.push_back(result.back());
        for (const auto &[v, id] : changes)
          result.back()[v] = id;
      }
    return result;
  }



  ExcMessage
  probe_outside(const Point<3> &p)
  {
    return ExcMessage("Geometry/Probe points: the point " +
                      format_point(p, 12) + " m does not lie in the solid.");
  }



  void
  check_coarsenable(const VoxelGrid &grid, const unsigned int level)
  {
    const unsigned int b = 1u << level;
    const auto        &n = grid.size();
    for (unsigned int d = 0; d < 3; ++d)
      AssertThrow(n[d] % b == 0,
                  ExcMessage("Geometry/Grid size: " + std::to_string(n[d]) +
                             " voxels along axis " + std::to_string(d) +
                             " is not divisible by " + std::to_string(b) +
                             ", the block size of coarsening level " +
                             std::to_string(level) +
                             " (asked for by Coarsening levels, by "
                             "Comparison/Levels in a compare run, or by "
                             "Database/Levels in a database run)."));
  }



  std::array<unsigned int, 3>
  block_origin(const VoxelGrid   &grid,
               const std::size_t  block,
               const unsigned int level)
  {
    const unsigned int width = 1u << level;
    const unsigned int m0 = grid.size()[0] / width, m1 = grid.size()[1] / width;
    return {
      {static_cast<unsigned int>(width * (block % m0)),
       static_cast<unsigned int>(width * ((block / m0) % m1)),
       static_cast<unsigned int>(width * (block / (std::size_t(m0) * m1)))}};
  }



  types::material_id
  dominant_material(const VoxelGrid   &grid,
                    const std::size_t  block,
                    const unsigned int level)
  {
    const unsigned int width = 1u << level;
    const auto         o     = block_origin(grid, block, level);
    // Voxels per id.
    std::array<unsigned int, std::numeric_limits<MaterialId>::max() + 1>
      count{};
    for (unsigned int k = 0; k < width; ++k)
      for (unsigned int j = 0; j < width; ++j)
        for (unsigned int i = 0; i < width; ++i)
          ++count[grid(o[0] + i, o[1] + j, o[2] + k)];
    types::material_id dominant = void_id;
    unsigned int       most     = 0;
    for (unsigned int id = void_id + 1; id < count.size(); ++id)
      if (count[id] > most) // ascending ids: ties keep the smaller
        {
          dominant = id;
          most     = count[id];
        }
    return dominant;
  }



  std::vector<std::size_t>
  make_voxel_mesh(const VoxelGrid   &grid,
                  const unsigned int level,
                  Triangulation<3>  &tria)
  {
    check_coarsenable(grid, level);
    const unsigned int                b = 1u << level;
    const auto                       &n = grid.size();
    const std::array<unsigned int, 3> m = {{n[0] / b, n[1] / b, n[2] / b}};
    const double                      H = grid.voxel_size() * b;

    // Blocks with at least one solid voxel, lexicographic; no more than
    // the memory of the machine can take as cells.
    const std::size_t        max_cells = cells_that_fit_in_memory();
    std::vector<std::size_t> blocks;
    for (unsigned int K = 0; K < m[2]; ++K)
      for (unsigned int J = 0; J < m[1]; ++J)
        for (unsigned int I = 0; I < m[0]; ++I)
          {
            bool solid = false;
            for (unsigned int k = 0; k < b && !solid; ++k)
              for (unsigned int j = 0; j < b && !solid; ++j)
                for (unsigned int i = 0; i < b && !solid; ++i)
                  solid = grid(b * I + i, b * J + j, b * K + k) != void_id;
            if (solid)
              blocks.push_back(I +
                               m[0] * (J + static_cast<std::size_t>(m[1]) * K));
            AssertThrow(
              blocks.size() <= max_cells,
              ExcMessage(
                "Geometry/Grid size = " + std::to_string(n[0]) + " x " +
                std::to_string(n[1]) + " x " + std::to_string(n[2]) +
                ": the scene has too many solid voxels for the memory of "
                "this machine. Its mesh at coarsening level " +
                std::to_string(level) + " would have more than " +
                std::to_string(max_cells) + " cells, and at " +
                std::to_string(minimum_bytes_per_cell / 1024) +
                " KiB or more per cell (about 20 KiB measured for a fine "
                "model) they need more than the " +
                format_number(physical_memory() / (1u << 30)) +
                " GiB of physical memory this machine has. Use fewer "
                "voxels: a smaller Grid size with a larger Voxel size."));
          }
    AssertThrow(!blocks.empty(), no_solid_voxel(grid));

    // Number only the vertices solid blocks use, in the order the blocks
    // first touch them. A vertex is found by its index in the grid of
    // block vertices among the sorted indices of the vertices used: memory
    // that grows with the solid blocks, not with the grid (two planes of
    // the grid's vertices took 1.4 GB for a flat grid of 12000 x 12000 x 1
    // voxels with 16 of them solid).
    const auto vertex_of = [&m](const std::size_t B, const unsigned int v) {
      const std::size_t I = B % m[0] + (v & 1),
                        J = (B / m[0]) % m[1] + ((v >> 1) & 1),
                        K = B / (std::size_t(m[0]) * m[1]) + ((v >> 2) & 1);
      return std::array<std::size_t, 4>{
        {I + (m[0] + 1) * (J + (m[1] + 1) * K), I, J, K}};
    };
    std::vector<std::size_t> used;
    used.reserve(8 * blocks.size());
    for (const std::size_t B : blocks)
      for (unsigned int v = 0; v < 8; ++v)
        used.push_back(vertex_of(B, v)[0]);
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    std::vector<unsigned int> number(used.size(),
                                     numbers::invalid_unsigned_int);
    std::vector<Point<3>>     vertices;
    vertices.reserve(used.size());
    std::vector<CellData<3>> cells(blocks.size());
    for (std::size_t c = 0; c < blocks.size(); ++c)
      {
        for (unsigned int v = 0; v < 8; ++v)
          {
            const auto [key, i, j, k] = vertex_of(blocks[c], v);
            unsigned int &index =
              number[std::lower_bound(used.begin(), used.end(), key) -
                     used.begin()];
            if (index == numbers::invalid_unsigned_int)
              {
                index = vertices.size();
                vertices.emplace_back(i * H, j * H, k * H);
              }
            cells[c].vertices[v] = index;
          }
        cells[c].material_id = dominant_material(grid, blocks[c], level);
      }

    tria.clear();
    tria.create_triangulation(vertices, cells, SubCellData());
    Assert(tria.n_active_cells() == blocks.size(), ExcInternalError());
    return blocks;
  }
} // namespace ddfem::scene
