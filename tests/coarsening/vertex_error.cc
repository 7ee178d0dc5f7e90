// The DDFEM paper's vertex error on known fields: the coarse field
// interpolated trilinearly to the fine vertices. An affine displacement is
// reproduced exactly by every level (error 0); a quadratic one has the
// known interpolation error H^2/4 at the midpoints of coarse edges; a
// perturbation of one fine vertex gives delta/L at that vertex.
//
// The coarse grid's best fit to a fine field (report::grid_fit), the
// trilinear field of least mean vertex error, reproduces an affine field on
// every level, with void voxels too. A bump of delta at the one interior
// vertex of a single block is best fitted by zero (any other field errs by
// more at the other 26 vertices than it gains at the centre): mean error
// delta/27 and max delta, both relative to L, and the lower bound agrees.
//
// The largest displacement of a coarse field over the solid's vertices
// (report::max_solid_displacement), of a single solid voxel of 0.25 m at
// the origin turned by 30 degrees about z: 2 sin(15 deg) sqrt(2) 0.25 m at
// its corners away from the axis, where the coarse nodes in void move by 2
// and 4 times that.

#include <ddfem/report/vertex_error.h>

#include <functional>

#include "../tests.h"

using namespace ddfem;
using namespace dealii;

namespace
{
  /// Interpolates f at the vertices (nodes) of @p d.
  Vector<double>
  nodal(const solver::Discretization                        &d,
        const std::function<Tensor<1, 3>(const Point<3> &)> &f)
  {
    Vector<double> u(d.dof_handler.n_dofs());
    for (const auto &cell : d.dof_handler.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        for (unsigned int c = 0; c < 3; ++c)
          u(cell->vertex_dof_index(v, c)) = f(cell->vertex(v))[c];
    return u;
  }
} // namespace

namespace
{
  /// The scene of @p grid_size voxels of @p voxel_size m, with @p shapes.
  std::unique_ptr<scene::Scene>
  make_scene(const std::string &grid_size,
             const double       voxel_size,
             const std::string &shapes = "")
  {
    ParameterHandler prm;
    app::declare_parameters(prm);
    prm.parse_input_from_string(
      "subsection Geometry\n set Grid size = " + grid_size +
      "\n set Voxel size = " + std::to_string(voxel_size) +
      "\nend\nsubsection Layout\n set Shapes = " + shapes + "\nend\n");
    auto scene = std::make_unique<scene::Scene>();
    scene->parse_parameters(prm);
    return scene;
  }
} // namespace

int
main()
{
  // A 4 x 4 x 8 voxel block of side 0.25 m: longest side 2 m.
  const auto                   scene_pointer = make_scene("4, 4, 8", 0.25);
  const scene::Scene          &scene         = *scene_pointer;
  const solver::Discretization fine(scene, 1);

  const auto affine = [](const Point<3> &x) {
    return Tensor<1, 3>({0.1 + 0.3 * x[0] - 0.2 * x[2],
                         -0.05 + 0.1 * x[1] + 0.4 * x[2],
                         0.02 * x[0] + 0.01 * x[1]});
  };
  const auto quadratic = [](const Point<3> &x) {
    return Tensor<1, 3>({x[0] * x[0], 0., 0.});
  };
  for (const unsigned int level : {1u, 2u})
    {
      const solver::Discretization coarse(scene, 1, level);
      std::cout << "Level " << level << ": " << coarse.cell_blocks.size()
                << " coarse cells" << std::endl;

      auto e = report::vertex_error(
        scene.grid, fine, nodal(fine, affine), coarse, nodal(coarse, affine));
      std::cout << "  affine: " << e.n_vertices << " fine vertices, length "
                << e.length << " m" << std::endl;
      testing::check_below("  affine mean error", e.mean, 1e-15);
      testing::check_below("  affine max error", e.max, 1e-15);

      // x^2 along x (0..1 m): coarse nodes every H = 0.25 * 2^level; the
      // interpolant is exact at coarse nodes and off by (H/2)^2 at edge
      // midpoints (level 1), by t(1-t)H^2 in general.
      e                         = report::vertex_error(scene.grid,
                               fine,
                               nodal(fine, quadratic),
                               coarse,
                               nodal(coarse, quadratic));
      const double H            = 0.25 * (1u << level);
      double       expected_sum = 0, expected_max = 0;
      for (unsigned int i = 0; i <= 4; ++i)
        {
          const double x = 0.25 * i;
          const double t = std::fmod(x, H) / H;
          expected_sum += t * (1 - t) * H * H;
          expected_max = std::max(expected_max, t * (1 - t) * H * H);
        }
      // The error depends on x alone, at five vertex positions; the
      // longest side is 2 m.
      const double mean = expected_sum / 5 / 2, max = expected_max / 2;
      std::cout << "  quadratic: mean " << e.mean << " (expected " << mean
                << "), max " << e.max << " (expected " << max << ")"
                << std::endl;
      testing::check_below("  quadratic: relative difference of the mean "
                           "and the max from the expected",
                           testing::worst(std::abs(e.mean / mean - 1),
                                          std::abs(e.max / max - 1)),
                           1e-12);
    }

  // One fine vertex moved by delta = 0.01 m against an exact coarse field.
  const solver::Discretization coarse(scene, 1, 1);
  Vector<double>               u_fine   = nodal(fine, affine);
  const Vector<double>         u_coarse = nodal(coarse, affine);
  const auto                   cell     = fine.dof_handler.begin_active();
  u_fine(cell->vertex_dof_index(7, 1)) += 0.01;
  const auto e =
    report::vertex_error(scene.grid, fine, u_fine, coarse, u_coarse);
  // The longest side is 2 m; the mean is over every vertex of the mesh.
  const double n_vertices = fine.triangulation.n_used_vertices();
  std::cout << "Perturbed vertex, " << e.n_vertices << " vertices" << std::endl;
  testing::check_below("  max error, relative difference to 0.01 / 2",
                       std::abs(e.max - 0.01 / 2) / (0.01 / 2),
                       1e-12);
  testing::check_below(
    "  mean error, relative difference to 0.01 / 2 / vertices",
    std::abs(e.mean - 0.01 / 2 / n_vertices) / (0.01 / 2 / n_vertices),
    1e-12);

  // The grid fit of an affine field is the field itself, also where
  // blocks are partly void (a column of void voxels along z, and one
  // voxel more).
  const auto                   carved = make_scene("4, 4, 8",
                                 0.25,
                                 "box 0 0 0 0.25 0.25 2 : 0; box 0.5 0.5 1 "
                                                   "0.75 0.75 1.25 : 0");
  const solver::Discretization carved_fine(*carved, 1);
  for (const unsigned int level : {1u, 2u})
    {
      const solver::Discretization coarse(*carved, 1, level);
      const Vector<double>         u = nodal(carved_fine, affine);
      const auto                   e =
        report::grid_fit(carved->grid, carved_fine, u, coarse).error;
      std::cout << "Carved grid, level " << level << ": "
                << carved->grid.n_solid_voxels() << " solid voxels, "
                << e.n_vertices << " fine vertices" << std::endl;
      testing::check_below("  grid fit of an affine field, max error",
                           e.max,
                           1e-12);
    }

  // A bump of delta at the centre of a single 2 x 2 x 2 block (side 0.5 m).
  const auto                   block = make_scene("2, 2, 2", 0.25);
  const solver::Discretization block_fine(*block, 1);
  const solver::Discretization block_coarse(*block, 1, 1);
  const double                 delta = 0.01;
  const auto                   bump  = [delta](const Point<3> &x) {
    return Tensor<1, 3>(
      {0., 0., (x - Point<3>(0.25, 0.25, 0.25)).norm() < 1e-12 ? delta : 0.});
  };
  const Vector<double> u_bump = nodal(block_fine, bump);
  const auto           fit =
    report::grid_fit(block->grid, block_fine, u_bump, block_coarse);
  const double expected_mean = delta / 27 / fit.error.length;
  std::cout << "Bump (expected mean error " << expected_mean << ", max "
            << delta / fit.error.length << "):" << std::endl;
  testing::check_below("  largest coarse nodal value / delta",
                       fit.field.linfty_norm() / delta,
                       1e-2);
  testing::check_below("  |mean error / expected - 1|",
                       std::abs(fit.error.mean / expected_mean - 1),
                       2e-3);
  testing::check_below("  |max error / expected - 1|",
                       std::abs(fit.error.max * fit.error.length / delta - 1),
                       1e-2);
  testing::check_below("  lower bound / expected - 1",
                       fit.lower_bound / expected_mean - 1,
                       1e-12);
  testing::check_below("  1 - lower bound / expected",
                       1 - fit.lower_bound / expected_mean,
                       2e-3);

  // A single solid voxel at the origin, turned rigidly by 30 degrees about
  // z: the trilinear field of every level reproduces it.
  const auto single =
    make_scene("4, 4, 4",
               0.25,
               "box 0 0 0 1 1 1 : 0; box 0 0 0 0.25 0.25 0.25 : 1");
  const Tensor<2, 3> R  = testing::rotation_about(Tensor<1, 3>({0, 0, 1}), 30);
  const double expected = 2 * std::sin(numbers::PI / 12) * std::sqrt(2.) * 0.25;
  std::cout << "A voxel turned by 30 degrees: largest displacement over the "
               "solid / "
            << expected
            << " m, over the model's nodes / the same:" << std::endl;
  for (const unsigned int level : {0u, 1u, 2u})
    {
      const solver::Discretization d(*single, 1, level);
      const Vector<double>         u =
        nodal(d, [&](const Point<3> &x) { return Tensor<1, 3>(R * x - x); });
      double nodes = 0;
      for (const auto &cell : d.dof_handler.active_cell_iterators())
        for (const unsigned int v : cell->vertex_indices())
          nodes =
            std::max(nodes, (R * cell->vertex(v) - cell->vertex(v)).norm());
      std::cout << "  level " << level << ": "
                << report::max_solid_displacement(single->grid, d, u) / expected
                << ", " << nodes / expected << std::endl;
    }
}
