// The loads of every model act on the fine solid. A coarse element whose
// block is partly void carries the body force over the block's solid voxels
// only, and a traction or pressure over the fine boundary faces in its
// region, weighted with the coarse shape functions: the coarse load vector
// is the fine load functional restricted to the coarse displacements. So
// fine, level-1 and level-2 models of a part with a notch carry the same
// total force and moment, the known ones. The total force f is read off
// the potential energy of the rigid translations c, E(c) = -f . c (a
// translation stores no elastic energy), and the moment M about the origin
// off that of the small rotations u = w x x: their elastic energy is even
// in w, so the central difference of E(w) and E(-w) is -2 M . w. A moment
// catches loads put on the wrong coarse nodes that keep the total force.
// The loads' work on all 24 trilinear fields, which every model represents,
// must be the fine model's (to 1e-12) at both levels; it catches wrong
// coarse load vectors that keep force and moment too. One of them has a
// known value: -756 J for u = (0, 0, x y) under the body force (1, -2, -3).
//
// Also: a Dirichlet condition on a box region whose node planes a coarse
// grid does not have is rejected for the coarse models, with a message
// naming the condition and the spacing, and accepted for the fine one.

#include <deal.II/dofs/dof_tools.h>

#include <ddfem/base/exceptions.h>
#include <ddfem/scene/boundary_conditions.h>
#include <ddfem/solver/supports.h>

#include "../tests.h"

using namespace ddfem;
using namespace dealii;

namespace
{
  /**
   * A 4 x 4 x 4 grid of voxels of 1 m, clamped at z = 0, with a notch of
   * void voxels at x < 1, z > 3 (so that level-1 and level-2 blocks are
   * partly void), and the loads @p loads (prm text).
   */
  std::string
  notched_block(const std::string &loads)
  {
    return R"(
      subsection Geometry
        set Grid size  = 4, 4, 4
        set Voxel size = 1
      end
      subsection Layout
        set Type   = uniform
        set Shapes = box 0 0 3 1 4 4 : 0
      end
      subsection Linear solver
        set Type = direct
      end
      subsection Boundary conditions
        subsection Condition 1
          set Type   = fixed
          set Region = z-
        end
      end
      )" + loads;
  }

  /// The potential energy of @p problem at load factor @p t at the
  /// displacement field @p u (a function of the point).
  template <typename Field>
  double
  energy_of(const testing::Problem &problem, const Field &u, const double t = 1)
  {
    const auto           &dof_handler = problem.discretization->dof_handler;
    std::vector<Point<3>> points(dof_handler.n_dofs());
    DoFTools::map_dofs_to_support_points(problem.discretization->mapping,
                                         dof_handler,
                                         points);
    const std::vector<unsigned int> component =
      solver::dof_components(dof_handler);
    Vector<double> values(dof_handler.n_dofs());
    for (unsigned int i = 0; i < values.size(); ++i)
      values(i) = u(points[i])[component[i]];
    return problem.solver->energy(values, t);
  }

  /// The potential energy of @p problem at the displacement field
  /// c + w x x, at full load.
  double
  rigid_motion_energy(const testing::Problem &problem,
                      const Tensor<1, 3>     &c,
                      const Tensor<1, 3>     &w)
  {
    return energy_of(problem, [&](const Point<3> &x) {
      return c + cross_product_3d(w, x);
    });
  }

  /**
   * The work of the loads of @p problem on the 24 trilinear fields m e_d
   * (m one of 1, x, y, z, xy, yz, zx, xyz; every model represents them
   * exactly), read off the energies at load factors 0 and 1 of 1e-6 of
   * each (dead loads: the difference is the loads' work alone). They probe
   * the coarse load vectors beyond the total force and moment.
   */
  std::vector<double>
  trilinear_works(const testing::Problem &problem)
  {
    const double        s = 1e-6;
    std::vector<double> works;
    for (unsigned int m = 0; m < 8; ++m)
      for (unsigned int d = 0; d < 3; ++d)
        {
          const auto field = [m, d, s](const Point<3> &x) {
            Tensor<1, 3> u;
            u[d] = s;
            for (unsigned int k = 0; k < 3; ++k)
              if (m & (1u << k))
                u[d] *= x[k];
            return u;
          };
          works.push_back(
            (energy_of(problem, field, 0) - energy_of(problem, field, 1)) / s);
        }
    return works;
  }

  /// The total external force of @p problem and its moment about the
  /// origin, from the energies of unit translations and of rotations by
  /// +-1e-3 rad (the round-off of their elastic energies leaves about
  /// 1e-9 of the moment).
  std::pair<Tensor<1, 3>, Tensor<1, 3>>
  force_and_moment(const testing::Problem &problem)
  {
    const double angle = 1e-3;
    Tensor<1, 3> force, moment;
    for (unsigned int d = 0; d < 3; ++d)
      {
        Tensor<1, 3> e;
        e[d]     = 1;
        force[d] = -rigid_motion_energy(problem, e, Tensor<1, 3>());
        moment[d] =
          -(rigid_motion_energy(problem, Tensor<1, 3>(), angle * e) -
            rigid_motion_energy(problem, Tensor<1, 3>(), -angle * e)) /
          (2 * angle);
      }
    return {force, moment};
  }

  /// "equal" if @p value is @p expected within @p tolerance of its size,
  /// else the value.
  std::string
  compare(const Tensor<1, 3> &value,
          const Tensor<1, 3> &expected,
          const double        tolerance)
  {
    if ((value - expected).norm() <= tolerance * expected.norm())
      return "equal";
    return "FAILED, (" + Utilities::to_string(value[0]) + " " +
           Utilities::to_string(value[1]) + " " +
           Utilities::to_string(value[2]) + ")";
  }

  void
  check_loads(const std::string  &name,
              const std::string  &loads,
              const Tensor<1, 3> &expected_force,
              const Tensor<1, 3> &expected_moment)
  {
    std::cout << name << ", expected force (" << expected_force
              << ") N, moment (" << expected_moment << ") N m:" << std::endl;
    std::vector<double> fine_works;
    for (const unsigned int level : {0u, 1u, 2u})
      {
        const testing::Problem problem(notched_block(loads), false, level);
        const auto [force, moment] = force_and_moment(problem);
        std::cout << "  level " << level << ": force "
                  << compare(force, expected_force, 1e-10) << ", moment "
                  << compare(moment, expected_moment, 1e-8) << std::endl;
        const std::vector<double> works = trilinear_works(problem);
        if (level == 0)
          fine_works = works;
        else
          {
            double largest = 0, difference = 0;
            for (unsigned int i = 0; i < works.size(); ++i)
              {
                largest = std::max(largest, std::abs(fine_works[i]));
                difference =
                  std::max(difference, std::abs(works[i] - fine_works[i]));
              }
            testing::check_below("    the 24 trilinear works against the "
                                 "fine model's, relative",
                                 difference / largest,
                                 1e-12);
          }
      }
  }

  /// Sets up the notched block with a second support on @p region at
  /// @p level and prints "accepted" or the message.
  void
  try_support(const std::string &region, const unsigned int level)
  {
    std::cout << "  \"" << region << "\", level " << level << ": ";
    try
      {
        const testing::Problem problem(notched_block(R"(
          subsection Boundary conditions
            subsection Condition 2
              set Type   = fixed
              set Region = )" + region + R"(
            end
          end)"),
                                       false,
                                       level);
        std::cout << "accepted" << std::endl;
      }
    catch (const ExceptionBase &e)
      {
        std::cout << message_of(e) << std::endl;
      }
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  // 60 solid voxels of 1 m^3: the cube's 64 with centroid (2, 2, 2) less
  // the notch's 4 with centroid (0.5, 2, 3.5), so the first moment of the
  // volume is (126, 120, 114) m^4.
  check_loads("Body force (1, -2, -3) N/m^3",
              "subsection Loads\n  set Body force = 1; -2; -3\nend\n",
              Tensor<1, 3>({60., -120., -180.}),
              Tensor<1, 3>({-132., 492., -372.}));
  // One trilinear work against its known value: on u = (0, 0, x y) the
  // body force (1, -2, -3) does -3 int x y dV = -3 (256 - 4) = -756 J.
  {
    const testing::Problem problem(
      notched_block("subsection Loads\n  set Body force = 1; -2; -3\nend\n"));
    testing::check_below("  the work on (0, 0, x y) against -756 J, relative",
                         std::abs(trilinear_works(problem)[3 * 3 + 2] / -756. -
                                  1),
                         1e-12);
  }
  // A body force that varies in space, (0, 0, x) N/m^3, is evaluated where
  // each cell's quadrature points are: force (0, 0, int x dV) and moment
  // (int x y dV, -int x^2 dV, 0), with int x y dV = 256 - 4 = 252 and
  // int x^2 dV = 1024/3 - 4/3 = 340 over the cube less the notch.
  check_loads("Body force (0, 0, x) N/m^3",
              "subsection Loads\n  set Body force = 0; 0; x\nend\n",
              Tensor<1, 3>({0., 0., 126.}),
              Tensor<1, 3>({252., -340., 0.}));
  // deal.II's if(condition, a, b) with no space after its commas (only
  // min(), max(), sum() and avg() are checked for decimal commas): (0, 0,
  // -1) N/m^3 for x > 1, on the 48 voxels of x from 1 to 4, y and z from 0
  // to 4 (the notch lies at x < 1), with int x dV = 120, int y dV = 96.
  check_loads("Body force if(x<1,0,-1) in z",
              "subsection Loads\n  set Body force = 0; 0; if(x<1,0,-1)\nend\n",
              Tensor<1, 3>({0., 0., -48.}),
              Tensor<1, 3>({-96., 120., 0.}));
  // The top face z = 4 has 12 solid voxel faces of 1 m^2, centroid
  // (2.5, 2, 4).
  check_loads("Traction (0, 0, -1) Pa on z+",
              R"(
      subsection Boundary conditions
        subsection Condition 2
          set Type   = traction
          set Region = z+
          set Value  = 0; 0; -1
        end
      end)",
              Tensor<1, 3>({0., 0., -12.}),
              Tensor<1, 3>({-24., 30., 0.}));
  // A traction that varies over the face, (0, 0, -x) Pa on z+ (x from 1
  // to 4, y from 0 to 4), is evaluated where each face's quadrature points
  // are: force (0, 0, -int x dA) and moment (-int x y dA, int x^2 dA, 0),
  // with int x dA = 30, int x y dA = 60 and int x^2 dA = 84.
  check_loads("Traction (0, 0, -x) Pa on z+",
              R"(
      subsection Boundary conditions
        subsection Condition 2
          set Type   = traction
          set Region = z+
          set Value  = 0; 0; -x
        end
      end)",
              Tensor<1, 3>({0., 0., -30.}),
              Tensor<1, 3>({-60., 84., 0.}));
  // The face x = 0 has 12 solid voxel faces (the notch takes 4 of 16),
  // centroid (0, 2, 1.5).
  check_loads("Pressure 2 Pa on x-",
              R"(
      subsection Boundary conditions
        subsection Condition 2
          set Type   = pressure
          set Region = x-
          set Value  = 2
        end
      end)",
              Tensor<1, 3>({24., 0., 0.}),
              Tensor<1, 3>({0., 36., -48.}));
  // The notch's floor (z = 3, x < 1) and wall (x = 1, z > 3): 8 faces whose
  // centers lie in the box, 4 of them inside level-1 and level-2 blocks;
  // centroids (0.5, 2, 3) and (1, 2, 3.5).
  check_loads("Traction (1, 0, 0) Pa on the notch's faces",
              R"(
      subsection Boundary conditions
        subsection Condition 2
          set Type   = traction
          set Region = box -1 -1 2.9 1.1 5 3.9
          set Value  = 1; 0; 0
        end
      end)",
              Tensor<1, 3>({8., 0., 0.}),
              Tensor<1, 3>({0., 26., -16.}));

  // Center = auto is the center of the region's part inside the grid: a
  // box that reaches past the 4 m grid to hold the top face turns the
  // node (4, 2, 4) by 90 degrees about z as the face z+ does, about
  // (2, 2, z), to (2, 4, 4), not about the box's own center (4, 4, z).
  std::cout << "Rotations about Center = auto:" << std::endl;
  for (const std::string region : {"z+", "box -1 -1 3.5 9 9 9"})
    {
      ParameterHandler prm;
      scene::BoundaryConditions::declare_parameters(prm);
      prm.parse_input_from_string(R"(
        subsection Boundary conditions
          subsection Condition 1
            set Type   = rotation
            set Region = )" + region +
                                  R"(
            set Axis   = 0, 0, 1
            set Angle  = 90
          end
        end)");
      scene::BoundaryConditions conditions;
      conditions.parse_parameters(prm, Point<3>(4, 4, 4), 1);
      Tensor<1, 3> u;
      for (unsigned int d = 0; d < 3; ++d)
        AssertThrow(
          conditions.prescribed_displacement(Point<3>(4, 2, 4), d, 1, u[d]),
          ExcMessage("the node is not held"));
      std::cout << "  \"" << region << "\": u(4, 2, 4) =";
      for (unsigned int d = 0; d < 3; ++d)
        std::cout << ' ' << (std::abs(u[d]) < 1e-12 ? 0. : u[d]);
      std::cout << " m" << std::endl;
    }

  std::cout << "Dirichlet conditions on boxes:" << std::endl;
  for (const std::string region :
       {"box -1 -1 3.5 5 5 5", "box -1 -1 1.5 5 5 5", "box 3 -1 -1 5 5 5"})
    for (const unsigned int level : {0u, 1u, 2u})
      try_support(region, level);
}
