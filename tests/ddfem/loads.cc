// The loads of every model act on the fine solid. A coarse element whose
// block is partly void carries the body force over the block's solid voxels
// only, and a traction or pressure over the fine boundary faces in its
// region, weighted with the coarse shape functions: the coarse load vector
// is the fine load functional restricted to the coarse displacements. So
// fine, level-1 and level-2 models of a part with a notch carry the same
// total force, the known one. The total force f is read off the potential
// energy of the rigid translations c, E(c) = -f . c (a translation stores
// no elastic energy).
//
// Also: a Dirichlet condition on a box region whose node planes a coarse
// grid does not have is rejected for the coarse models, with a message
// naming the condition and the spacing, and accepted for the fine one.

#include <ddfem/base/exceptions.h>

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

  /// The total external force of @p problem, from the energy of the unit
  /// translations.
  Tensor<1, 3>
  total_force(const testing::Problem &problem)
  {
    const auto  &dof_handler = problem.discretization->dof_handler;
    Tensor<1, 3> force;
    for (unsigned int d = 0; d < 3; ++d)
      {
        Vector<double> u(dof_handler.n_dofs());
        for (const auto &cell : dof_handler.active_cell_iterators())
          for (unsigned int i = 0; i < cell->get_fe().n_dofs_per_cell(); ++i)
            if (cell->get_fe().system_to_component_index(i).first == d)
              {
                std::vector<types::global_dof_index> dofs(
                  cell->get_fe().n_dofs_per_cell());
                cell->get_dof_indices(dofs);
                u(dofs[i]) = 1;
              }
        force[d] = -problem.solver->energy(u, 1.);
      }
    return force;
  }

  void
  check_loads(const std::string  &name,
              const std::string  &loads,
              const Tensor<1, 3> &expected)
  {
    std::cout << name << ", expected force (" << expected
              << ") N:" << std::endl;
    for (const unsigned int level : {0u, 1u, 2u})
      {
        const testing::Problem problem(notched_block(loads), false, level);
        const Tensor<1, 3>     force = total_force(problem);
        std::cout << "  level " << level << ": "
                  << ((force - expected).norm() <= 1e-10 * expected.norm() ?
                        "equal" :
                        "FAILED, force (" + Utilities::to_string(force[0]) +
                          " " + Utilities::to_string(force[1]) + " " +
                          Utilities::to_string(force[2]) + ")")
                  << std::endl;
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

  // 60 solid voxels of 1 m^3.
  check_loads("Body force (1, -2, -3) N/m^3",
              "subsection Loads\n  set Body force = 1; -2; -3\nend\n",
              Tensor<1, 3>({60., -120., -180.}));
  // The top face z = 4 has 12 solid voxel faces of 1 m^2.
  check_loads("Traction (0, 0, -1) Pa on z+",
              R"(
      subsection Boundary conditions
        subsection Condition 2
          set Type   = traction
          set Region = z+
          set Value  = 0; 0; -1
        end
      end)",
              Tensor<1, 3>({0., 0., -12.}));
  // The face x = 0 has 12 solid voxel faces (the notch takes 4 of 16).
  check_loads("Pressure 2 Pa on x-",
              R"(
      subsection Boundary conditions
        subsection Condition 2
          set Type   = pressure
          set Region = x-
          set Value  = 2
        end
      end)",
              Tensor<1, 3>({24., 0., 0.}));
  // The notch's floor (z = 3, x < 1) and wall (x = 1, z > 3): 8 faces whose
  // centers lie in the box, 4 of them inside level-1 and level-2 blocks.
  check_loads("Traction (1, 0, 0) Pa on the notch's faces",
              R"(
      subsection Boundary conditions
        subsection Condition 2
          set Type   = traction
          set Region = box -1 -1 2.9 1.1 5 3.9
          set Value  = 1; 0; 0
        end
      end)",
              Tensor<1, 3>({8., 0., 0.}));

  std::cout << "Dirichlet conditions on boxes:" << std::endl;
  for (const std::string region :
       {"box -1 -1 3.5 5 5 5", "box -1 -1 1.5 5 5 5", "box 3 -1 -1 5 5 5"})
    for (const unsigned int level : {0u, 1u, 2u})
      try_support(region, level);
}
