// The ways Newton's method fails that no other test reaches, on one voxel
// of 1 cm clamped on its y- face. Each case is solved in one load increment
// that may not be cut (Load steps = 1, Minimum load step = 1):
// 1. No descent direction: a traction of 1e300 Pa on E = 1e-19 Pa, a load
//    beyond double precision for the material (dg/bad_penalty's
//    infinite_solution). The solution overflows for the tangent and for
//    every shift of it, up to 1e4 times its diagonal, so all ten solves
//    fail; the increment fails with the reason of the last solve and the
//    largest shift, and the log says "no descent direction found". With
//    UMFPACK, and with the sparse Cholesky solver (cg-cholesky, the one
//    'auto' takes for small models), whose overflowing solve is a failure
//    as UMFPACK's is (it went on into a non-finite line search).
// 2. The line search on the boundary values: a compressive traction of
//    1e16 Pa on E = 1e5 Pa. The Newton step descends, but shortens the
//    voxel by some 1e10 times its height, so that even 2^-29 of it turns the
//    voxel inside out: no trial state is admissible (it said that no step
//    lowers the energy, which hid the cause).
// 3. The line search toward the boundary values: the y+ face is to move by
//    -1e9 m. Every node is held, so det F = 1 - 1e11 a for a step a, and
//    a = 2^-29 still gives det F < 0: no trial state is admissible.
// Each case prints the solver's log and the statistics of the failed solve.

#include <sstream>

#include "../tests.h"

using namespace ddfem;

namespace
{
  /**
   * Prints @p title, then the solver's log and the statistics of a solve of
   * the parameter text @p prm in one uncut increment with the linear solver
   * @p linear_solver.
   */
  void
  report(const std::string &title,
         const std::string &prm,
         const std::string &linear_solver)
  {
    std::ostringstream log;
    testing::Problem   problem(prm +
                               "subsection Nonlinear solver\n"
                                 "  set Load steps = 1\n"
                                 "  set Minimum load step = 1\n"
                                 "end\n"
                                 "subsection Linear solver\n"
                                 "  set Type = " +
                               linear_solver + "\nend\n",
                             true,
                             0,
                             log);
    const auto         statistics = problem.solve();
    std::cout << title << " (" << linear_solver << ")" << std::endl
              << log.str() << "  converged: " << std::boolalpha
              << statistics.converged << ", " << statistics.describe()
              << ", shifted iterations " << statistics.regularized_iterations
              << ", UMFPACK solves " << statistics.direct_solves << std::endl;
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  const std::string overflow =
    testing::cantilever("1, 1, 1", "0; 0; -1e300") +
    "subsection Materials\n  set Palette = E=1e-19 nu=0.3\nend\n";
  report("1. Traction 1e300 Pa on E = 1e-19 Pa: every solve overflows",
         overflow,
         "direct");
  report("1. Traction 1e300 Pa on E = 1e-19 Pa: every solve overflows",
         overflow,
         "cg-cholesky");
  report("2. Compressive traction 1e16 Pa on E = 1e5 Pa: every trial step "
         "inverts the voxel",
         testing::cantilever("1, 1, 1", "0; -1e16; 0"),
         "direct");
  report("3. The y+ face moved by -1e9 m: every step toward it inverts the "
         "voxel",
         testing::cantilever("1, 1, 1", "0; -1e9; 0") +
           "subsection Boundary conditions\n  subsection Condition 2\n"
           "    set Type = displacement\n  end\nend\n",
         "direct");
}
