// RigidPartConditions against the kinematics of hinged parts: a part held
// at two points is free to turn about the line through them; two such
// parts joined along a third line form a three-hinged arch, rigid unless
// the three hinge lines lie in one plane (then it has one infinitesimal
// mechanism); two parts joined along one line and held by nothing move as
// one rigid body plus the hinge's rotation (7 motions). Every free motion is
// checked to satisfy the conditions, from the parts' velocities computed
// here: held points do not move, joined points move alike in both parts.
// The sparse count of free motions agrees with the dense basis. The mesh
// check counts the mechanism of rotating squares (a checkerboard layer of
// voxels hinged at their z edges) at any size. Cells across a hanging face
// are one face-connected part.

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <ddfem/base/exceptions.h>
#include <ddfem/scene/scene.h>
#include <ddfem/solver/supports.h>

#include <optional>
#include <set>

#include "../tests.h"

using namespace ddfem;
using namespace dealii;

namespace
{
  /// A hinge line along z: the points (x, y, 0) and (x, y, 1).
  std::vector<Point<3>>
  hinge(const double x, const double y)
  {
    return {Point<3>(x, y, 0), Point<3>(x, y, 1)};
  }

  /// The velocity at @p x of part @p part in free motion @p r of
  /// @p motions (per part: translation, then angular velocity about
  /// @p center), computed here rather than by rigid_body_modes().
  Tensor<1, 3>
  velocity(const FullMatrix<double> &motions,
           const unsigned int        r,
           const unsigned int        part,
           const Point<3>           &x,
           const Point<3>           &center)
  {
    Tensor<1, 3> t, w;
    for (unsigned int d = 0; d < 3; ++d)
      {
        t[d] = motions(6 * part + d, r);
        w[d] = motions(6 * part + 3 + d, r);
      }
    return t + cross_product_3d(w, x - center);
  }

  /// The largest speed of a held point of the free motions @p motions
  /// (@p held: per part, its held points), and the largest difference of
  /// the velocities of parts 0 and 1 at the joined points @p joint.
  double
  violation(const FullMatrix<double>                 &motions,
            const std::vector<std::vector<Point<3>>> &held,
            const std::vector<Point<3>>              &joint,
            const Point<3>                           &center)
  {
    double largest = 0;
    for (unsigned int r = 0; r < motions.n(); ++r)
      {
        for (unsigned int part = 0; part < held.size(); ++part)
          for (const Point<3> &x : held[part])
            largest =
              testing::worst(largest,
                             velocity(motions, r, part, x, center).norm());
        for (const Point<3> &x : joint)
          largest = testing::worst(largest,
                                   (velocity(motions, r, 0, x, center) -
                                    velocity(motions, r, 1, x, center))
                                     .norm());
      }
    return largest;
  }

  /// Parts 0 and 1 held along the lines at @p a and @p b (if given) and
  /// joined along the line at @p c: the number of free motions.
  void
  report(const std::string             &name,
         const std::optional<Point<2>> &a,
         const std::optional<Point<2>> &b,
         const Point<2>                &c)
  {
    const Point<3>                     center(1, 0.5, 0.5);
    solver::RigidPartConditions        conditions(2, center, 1.);
    std::vector<std::vector<Point<3>>> held(2);
    for (unsigned int part = 0; part < 2; ++part)
      if (const auto &at = (part == 0 ? a : b); at)
        for (const Point<3> &x : hinge((*at)[0], (*at)[1]))
          {
            held[part].push_back(x);
            for (unsigned int d = 0; d < 3; ++d)
              conditions.hold(x, d, part);
          }
    const std::vector<Point<3>> joint = hinge(c[0], c[1]);
    for (const Point<3> &x : joint)
      for (unsigned int d = 0; d < 3; ++d)
        conditions.join(x, d, 0, 1);
    const FullMatrix<double> motions = conditions.free_motions();
    std::cout << name << ": " << motions.n() << " free motion(s)"
              << (conditions.n_free_motions() == motions.n() ?
                    "" :
                    ", but n_free_motions() counts " +
                      std::to_string(conditions.n_free_motions()))
              << std::endl;
    testing::check_below("  speed of held points, velocity difference at "
                         "joined points",
                         violation(motions, held, joint, center),
                         1e-12);
    // The one motion with the joint on the line of the supports: each
    // part turns about its support, about z, the two at opposite rates
    // (the joint moves along y alike in both).
    if (motions.n() == 1 && a && b)
      std::cout << "  rates about z, part 0 / part 1: "
                << motions(5, 0) / motions(11, 0) << std::endl;
  }
  /**
   * require_supported_mesh() on a checkerboard of n x n x @p layers voxels
   * (solid where i + j + k is even, the four corners of the first layer
   * void, so every voxel of a single layer hangs on two z edges), held at
   * every node of the voxels (i, 0, 0) for i in @p clamped. A single layer
   * is a lattice of rotating squares: with one voxel held the others turn
   * alternately by two angles, one free motion; a second held voxel stops
   * it, as the lattice's expansion would move it. Two layers interlock
   * along edges in all three directions and are rigid. No voxel shares a
   * face, so every part is one voxel and only the group check can tell.
   */
  void
  report_checkerboard(const unsigned int               n,
                      const unsigned int               layers,
                      const std::vector<unsigned int> &clamped)
  {
    scene::VoxelGrid grid({{n, n, layers}}, 1.);
    for (unsigned int k = 0; k < layers; ++k)
      for (unsigned int j = 0; j < n; ++j)
        for (unsigned int i = 0; i < n; ++i)
          if ((i + j + k) % 2 == 0 &&
              !(k == 0 && (i == 0 || i == n - 1) && (j == 0 || j == n - 1)))
            grid(i, j, k) = 1;
    Triangulation<3>               tria;
    const std::vector<std::size_t> voxel =
      scene::make_voxel_mesh(grid, 0, tria);
    std::set<unsigned int> held;
    for (const auto &cell : tria.active_cell_iterators())
      for (const unsigned int i : clamped)
        if (voxel[cell->active_cell_index()] == grid.index(i, 0, 0))
          for (const unsigned int v : cell->vertex_indices())
            held.insert(cell->vertex_index(v));
    std::vector<std::vector<solver::ConstrainedRow>> cell_rows(
      tria.n_active_cells());
    for (const auto &cell : tria.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        if (held.count(cell->vertex_index(v)) > 0)
          for (unsigned int d = 0; d < 3; ++d)
            cell_rows[cell->active_cell_index()].emplace_back(cell->vertex(v),
                                                              d);
    std::cout << "checkerboard of " << n << " x " << n << " x " << layers
              << " voxels (" << tria.n_active_cells() << " solid), "
              << clamped.size() << " clamped: ";
    try
      {
        solver::require_supported_mesh(tria, cell_rows);
        std::cout << "supported" << std::endl;
      }
    catch (const ExceptionBase &e)
      {
        std::cout << message_of(e) << std::endl;
      }
  }
} // namespace

int
main()
{
  // fixed_rigid_modes() of known supports. A plate of L x L voxels (size h)
  // held in z at every bottom node, counted per cell as the checks count
  // them, and in x and y at two neighbouring nodes: all six are fixed,
  // though the turn about z has a lever of h only (from L = 241 on, five
  // were counted). The same without the second node: five.
  {
    const unsigned int                  L = 300;
    std::vector<solver::ConstrainedRow> rows;
    for (unsigned int i = 0; i < L; ++i)
      for (unsigned int j = 0; j < L; ++j)
        for (unsigned int v = 0; v < 4; ++v)
          rows.emplace_back(Point<3>(i + v % 2, j + v / 2, 0), 2);
    rows.emplace_back(Point<3>(0, 0, 0), 0);
    rows.emplace_back(Point<3>(0, 0, 0), 1);
    std::cout << "plate held at one node in x and y: "
              << solver::fixed_rigid_modes(rows) << " modes fixed" << std::endl;
    rows.emplace_back(Point<3>(1, 0, 0), 1);
    rows.emplace_back(Point<3>(1, 0, 0), 1);
    std::cout << "and at its neighbour in y: "
              << solver::fixed_rigid_modes(rows) << " modes fixed" << std::endl;
    // A bar of N voxels held along an edge line, in all components, is
    // free to turn about it; one row in z at a node off the line stops
    // that (from N = 2714 on, it was not counted).
    const unsigned int N = 3000;
    rows.clear();
    for (unsigned int i = 0; i < N; ++i)
      for (unsigned int v = 0; v < 2; ++v)
        for (unsigned int d = 0; d < 3; ++d)
          rows.emplace_back(Point<3>(i + v, 0, 0), d);
    std::cout << "bar held along an edge line: "
              << solver::fixed_rigid_modes(rows) << " modes fixed";
    rows.emplace_back(Point<3>(0, 1, 0), 2);
    std::cout << ", and in z at one node off it: "
              << solver::fixed_rigid_modes(rows) << std::endl;
  }

  // One part held along one line: the rotation about it.
  {
    solver::RigidPartConditions conditions(1, Point<3>(0, 0, 0.5), 1.);
    for (const Point<3> &x : hinge(0, 0))
      for (unsigned int d = 0; d < 3; ++d)
        conditions.hold(x, d, 0);
    const FullMatrix<double> motion = conditions.free_motions();
    std::cout << "one part held along a line: " << motion.n()
              << " free motion(s)";
    if (motion.n() == 1)
      std::cout << ", rotation about z " << std::abs(motion(5, 0))
                << ", other components "
                << (std::abs(motion(0, 0)) + std::abs(motion(1, 0)) +
                          std::abs(motion(2, 0)) + std::abs(motion(3, 0)) +
                          std::abs(motion(4, 0)) <
                        1e-12 ?
                      "below 1e-12" :
                      "ABOVE 1e-12");
    std::cout << std::endl;
  }
  report("arch, joint off the line of its supports",
         Point<2>(0, 0),
         Point<2>(2, 0),
         Point<2>(1, 1));
  report("arch, joint on the line of its supports",
         Point<2>(0, 0),
         Point<2>(2, 0),
         Point<2>(1, 0));
  report("two parts joined along a line, held nowhere",
         std::nullopt,
         std::nullopt,
         Point<2>(1, 0));

  // The mechanism of a group of more than 200 parts (the limit of the
  // dense count this check used), and groups that are held.
  report_checkerboard(11, 1, {4});
  report_checkerboard(41, 1, {20});
  report_checkerboard(41, 1, {20, 30});
  report_checkerboard(21, 2, {10});
  report_checkerboard(41, 2, {20});

  // Parts across a hanging face: two cells, one of them refined, are one
  // part, joined from the refined side (the coarse side's neighbor has no
  // active cell index).
  {
    Triangulation<3> tria;
    GridGenerator::subdivided_hyper_rectangle(tria,
                                              {2, 1, 1},
                                              Point<3>(0, 0, 0),
                                              Point<3>(2, 1, 1));
    tria.begin_active()->set_refine_flag();
    tria.execute_coarsening_and_refinement();
    solver::Components    parts = solver::face_connected_parts(tria);
    std::set<std::size_t> distinct;
    for (unsigned int c = 0; c < tria.n_active_cells(); ++c)
      distinct.insert(parts.find(c));
    std::cout << tria.n_active_cells()
              << " cells, one of two refined: " << distinct.size()
              << " face-connected part(s)" << std::endl;
  }
}
