// Results and the number of threads (doc/fine_solver.md, "Parallelism and
// determinism"). A heterogeneous cantilever under a tip traction solved
// with one thread and with two:
// - 7623 DoFs, with a body force as well (its load vector is integrated
//   cell by cell): the assembly (WorkStream) runs threaded, the vector
//   operations of CG do not (deal.II threads them from 16384 entries on);
//   the solutions must be the same bit for bit, with the
//   Cholesky-preconditioned and the multigrid CG;
// - 19575 DoFs: deal.II's vector reductions split their sums into chunks
//   by the number of threads, so the solutions differ in round-off only,
//   and two runs with two threads must give the same solution bit for bit.
//   (7.6e-16 measured; the bound is 1e-14.) No body force here: with it,
//   the last Newton step's inexact CG solve, which the reductions steer,
//   left differences of 6.9e-13 in a trial, not round-off.

#include "../threads.h"

#include <deal.II/base/multithread_info.h>

#include "../tests.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  /// The solution of the cantilever of @p grid voxels with the linear
  /// solver @p type and @p threads threads, with the body force
  /// @p body_force ("fx; fy; fz", N/m^3).
  Vector<double>
  solve(const std::string &grid,
        const std::string &type,
        const unsigned int threads,
        const std::string &body_force = "0; 0; 0")
  {
    MultithreadInfo::set_thread_limit(threads);
    testing::Problem problem(
      testing::cantilever(grid, "0; 0; -5000") + testing::layers("0.01", "z") +
      "subsection Geometry\n  set Voxel size = 0.005\nend\n"
      "subsection Nonlinear solver\n  set Load steps = 2\nend\n"
      "subsection Loads\n  set Body force = " +
      body_force +
      "\nend\n"
      "subsection Linear solver\n  set Type = " +
      type + "\nend\n");
    const auto statistics = problem.solve();
    std::cout << "  " << problem.discretization->dof_handler.n_dofs()
              << " DoFs, " << type << ", " << MultithreadInfo::n_threads()
              << " thread(s): "
              << (statistics.converged ? "converged" : "FAILED") << " in "
              << statistics.newton_iterations << " Newton iterations"
              << std::endl;
    return problem.solver->solution();
  }

  /// max |a - b| / max |a|.
  double
  difference(const Vector<double> &a, Vector<double> b)
  {
    b -= a;
    return b.linfty_norm() / a.linfty_norm();
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  std::cout << "Threads running a WorkStream with the limit 1: "
            << testing::threads_running(1)
            << ", with the limit 2: " << testing::threads_running(2)
            << std::endl;
  std::cout << "Threaded assembly:" << std::endl;
  for (const std::string type : {"cg-cholesky", "cg-amg"})
    {
      const std::string    force = "0; 0; -2e4 * (1 + 10 * y)";
      const Vector<double> one   = solve("10, 20, 10", type, 1, force);
      const Vector<double> two   = solve("10, 20, 10", type, 2, force);
      std::cout << "  one and two threads: "
                << (difference(one, two) == 0 ? "identical" : "DIFFERENT")
                << std::endl;
    }

  std::cout << "Threaded assembly and vector operations:" << std::endl;
  const Vector<double> one       = solve("14, 28, 14", "cg-amg", 1);
  const Vector<double> two       = solve("14, 28, 14", "cg-amg", 2);
  const Vector<double> two_again = solve("14, 28, 14", "cg-amg", 2);
  std::cout << "  two runs with two threads: "
            << (difference(two, two_again) == 0 ? "identical" : "DIFFERENT")
            << std::endl
            << "  one and two threads, ";
  testing::check_below("max |difference| / max |u|",
                       difference(one, two),
                       1e-14);
}
