// Newton's line search where the energy is at round-off: near the solution
// the decrease Armijo's condition asks of a step, 1e-4 a |R . du|, falls
// below the round-off of the energy sum, which then decides the test. Within
// 1e3 times that round-off a step is accepted instead if it lowers the
// residual, and the log marks it. A cube of 2^3 voxels on three sliding
// faces (x-, y-, z-) under a traction T on its z+ face is in uniaxial
// stress, F = diag(s, s, b), with
//   mu s^2 + lambda ln J - mu = 0 and mu b + (lambda ln J - mu) / b = T,
// J = s^2 b. Solved to the smallest Newton tolerance (1e-14) in one
// increment, its Newton iteration 4 takes a full step on the residual test,
// from |R| = 1.1e-12 N to 1.1e-14 N, below the tolerance's 3e-14 N. With
// the test disabled (tried), Armijo's condition passed a quarter step on
// round-off and the iteration ended on the size of the Newton correction
// at |R| = 8.6e-13 N, 29 times the tolerance, which the test's check of
// the final residual rejects. The displacement at every node matches the
// exact one to round-off. The tangent is assembled once per Newton step:
// the converged state's residual comes from the line search's assembly of
// it, and its tangent would go unused.

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>

#include <array>
#include <sstream>

#include "../tests.h"

using namespace ddfem;
using namespace dealii;

namespace
{
  /// The stretches (s, b) of uniaxial stress T in the Neo-Hookean
  /// material (mu, lambda), by Newton's method on the two equations.
  std::pair<double, double>
  uniaxial_stretches(const double mu, const double lambda, const double T)
  {
    double s = 1, b = 1;
    for (unsigned int i = 0; i < 50; ++i)
      {
        const double log_J = std::log(s * s * b);
        const double f1    = mu * s * s + lambda * log_J - mu,
                     f2    = mu * b + (lambda * log_J - mu) / b - T;
        const double a11 = 2 * mu * s + 2 * lambda / s, a12 = lambda / b,
                     a21 = 2 * lambda / (s * b),
                     a22 =
                       mu + lambda / (b * b) - (lambda * log_J - mu) / (b * b);
        const double det = a11 * a22 - a12 * a21;
        s -= (a22 * f1 - a12 * f2) / det;
        b -= (a11 * f2 - a21 * f1) / det;
      }
    return {s, b};
  }

  /**
   * Solves the cube under the traction @p T Pa to the Newton tolerance
   * @p tolerance in one increment; prints the solver's log, whether it
   * converged, the largest nodal displacement error relative to the
   * exact lid displacement, which must be below @p bound, and the final
   * residual at the free unknowns, which must be within the tolerance.
   */
  void
  solve_cube(const double T, const double tolerance, const double bound)
  {
    std::ostringstream prm;
    std::ostringstream traction;
    traction << std::setprecision(17) << "0; 0; " << T;
    prm << std::setprecision(17)
        << "subsection Geometry\n  set Grid size = 2, 2, 2\n"
           "  set Voxel size = 0.01\nend\n"
           "subsection Materials\n  set Palette = E=1e5 nu=0.3\nend\n"
        << testing::uniaxial_conditions("traction", traction.str())
        << "subsection Nonlinear solver\n  set Load steps = 1\n"
           "  set Minimum load step = 1\n  set Newton tolerance = "
        << tolerance << "\nend\n"
        << "subsection Linear solver\n  set Type = direct\nend\n";

    std::ostringstream log;
    testing::Problem   problem(prm.str(), true, 0, log);
    const auto         statistics = problem.solve();

    const double E = 1e5, nu = 0.3, mu = E / (2 * (1 + nu)),
                 lambda                = E * nu / ((1 + nu) * (1 - 2 * nu));
    const auto [s, b]                  = uniaxial_stretches(mu, lambda, T);
    const std::array<double, 3> strain = {{s - 1, s - 1, b - 1}};

    const auto           &dof_handler = problem.discretization->dof_handler;
    std::vector<Point<3>> points(dof_handler.n_dofs());
    DoFTools::map_dofs_to_support_points(problem.discretization->mapping,
                                         dof_handler,
                                         points);
    const Vector<double> &u     = problem.solver->solution();
    double                error = 0;
    // The sliding faces hold the component normal to them.
    std::vector<bool>                    held(dof_handler.n_dofs());
    std::vector<types::global_dof_index> dofs(
      dof_handler.get_fe().n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        cell->get_dof_indices(dofs);
        for (unsigned int i = 0; i < dofs.size(); ++i)
          {
            const unsigned int d =
              dof_handler.get_fe().system_to_component_index(i).first;
            held[dofs[i]] = points[dofs[i]][d] < 1e-12;
            error         = testing::worst(error,
                                   std::abs(u(dofs[i]) -
                                            strain[d] * points[dofs[i]][d]));
          }
      }
    // The norm of the residual at the free unknowns in the state @p v: at
    // rest it is the load's, which is the solver's reference here (its
    // largest residual, that of the first iteration).
    const auto free_residual_norm = [&](const Vector<double> &v) {
      Vector<double>       residual;
      SparseMatrix<double> tangent;
      problem.solver->residual_and_tangent(v, 1., residual, tangent);
      for (unsigned int i = 0; i < residual.size(); ++i)
        if (held[i])
          residual(i) = 0;
      return residual.l2_norm();
    };
    const double relative_residual =
      free_residual_norm(u) /
      (tolerance * free_residual_norm(Vector<double>(u.size())));

    std::cout << "Traction " << T << " Pa, Newton tolerance " << tolerance
              << std::endl
              << log.str() << "  converged: " << std::boolalpha
              << statistics.converged << ", " << statistics.describe()
              << std::endl
              << "  exact stretches: lateral " << std::setprecision(10) << s
              << ", axial " << b << std::setprecision(6) << std::endl;
    testing::check_below("  largest nodal displacement error / lid "
                         "displacement",
                         error / std::abs((b - 1) * 0.02),
                         bound);
    testing::check_below("  final residual / (Newton tolerance * load)",
                         relative_residual,
                         1);
    std::cout
      << "  tangent assemblies: "
      << problem.timer.get_summary_data(TimerOutput::n_calls).at("assembly")
      << std::endl;
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  solve_cube(2e4, 1e-14, 1e-12);
}
