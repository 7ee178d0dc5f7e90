// The linear solvers on Neo-Hookean tangents of a random heterogeneous block
// (made definite by a small diagonal shift, as the Dirichlet rows do in a
// solve):
// 1. the CHOLMOD Cholesky factor solves K x = b to round-off and agrees
//    with UMFPACK; a refactorization on the same pattern (another matrix)
//    is as accurate, also after the factor was dropped (as after a material
//    edit); a matrix that is not positive definite is reported,
//    and leaves no factor, also a simplicial factor (a tridiagonal matrix),
//    which CHOLMOD's default L D L^T would accept;
// 2. cg-cholesky factorizes the first tangent (1 iteration), solves the
//    next, nearby tangent by a few CG iterations with the old factor to the
//    requested tolerance, factorizes again when a tangent is too far from
//    the factored one (CG needs more than 'Cholesky factorization cost'
//    iterations), and hands an indefinite tangent to UMFPACK (after CG
//    fails), and the next 1, 2, 4, then 8 systems at once while
//    factorizations keep failing, until a factorization succeeds (a
//    Failure of UMFPACK counts the CG iterations spent before); a solve
//    that needs more iterations
//    than the average cost per solve of its factor (the factorization
//    counted as 'Cholesky factorization cost') makes the next system be
//    factorized at once, and one that needs more than the CG solves before
//    it, but not more than that average, does not;
// 3. auto's cg-amg hands a system on which CG fails to UMFPACK;
// 4. cg-amg builds its near null space on the deformed shape;
// 5. cg-amg keeps its multigrid hierarchy while only the tolerance
//    tightens (inexact Newton's last solves), and builds a new one after a
//    solve that needed more than 1.5 times the iterations per decade of
//    residual reduction of the first solve with it; a solve that fails
//    with an earlier tangent's hierarchy is tried again with its own.

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/lac/sparse_direct.h>

#include <ddfem/base/exceptions.h>
#include <ddfem/solver/sparse_cholesky.h>
#include <ddfem/solver/supports.h>

#include <random>

#include "../tests.h"

using namespace ddfem;
using namespace dealii;

namespace
{
  /// Relative residual |K x - b| / |b|.
  double
  relative_residual(const SparseMatrix<double> &K,
                    const Vector<double>       &x,
                    const Vector<double>       &b)
  {
    Vector<double> r(b.size());
    K.vmult(r, x);
    r -= b;
    return r.l2_norm() / b.l2_norm();
  }

  /// The tangent @p K of @p problem at a random displacement (seed 11) of
  /// components up to @p amplitude, shifted by 1e-3 of its mean diagonal.
  void
  shifted_tangent(testing::Problem     &problem,
                  const double          amplitude,
                  SparseMatrix<double> &K)
  {
    const unsigned int n = problem.discretization->dof_handler.n_dofs();
    std::mt19937       same(11);
    std::uniform_real_distribution<double> uniform(-1, 1);
    Vector<double>                         u(n), residual;
    for (auto &v : u)
      v = amplitude * uniform(same);
    problem.solver->residual_and_tangent(u, 1., residual, K);
    double trace = 0;
    for (unsigned int i = 0; i < n; ++i)
      trace += K.diag_element(i);
    for (unsigned int i = 0; i < n; ++i)
      K.diag_element(i) += 1e-3 * trace / n;
  }

  /// A LinearSolver with the entries @p settings of its 'Linear solver'
  /// subsection, initialized for the unknowns of @p dof_handler, and the
  /// timer it reports to (which outlives it).
  struct TimedSolver
  {
    TimedSolver(const std::string &settings, const DoFHandler<3> &dof_handler)
      : timer(std::cout, TimerOutput::never, TimerOutput::wall_times)
    {
      ParameterHandler prm;
      solver::LinearSolver::declare_parameters(prm);
      prm.parse_input_from_string("subsection Linear solver\n" + settings +
                                  "\nend\n");
      linear_solver.parse_parameters(prm);
      linear_solver.initialize(dof_handler, timer);
    }

    /// Receives the solver's timing sections.
    TimerOutput timer;
    /// The solver under test.
    solver::LinearSolver linear_solver;
  };
} // namespace



int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  testing::Problem   problem(testing::cantilever("4, 4, 4", "1e3; -2e3; 5e2") +
                           R"(
    subsection Layout
      set Type = random
    end)");
  const unsigned int n = problem.discretization->dof_handler.n_dofs();
  std::mt19937       random(3);
  std::uniform_real_distribution<double> uniform(-1, 1);

  // Tangents at two displacements (strains of about 1 % and 2 %), each
  // shifted by 1e-3 of its mean diagonal, and a matrix far from both: the
  // second tangent with the diagonal of half its rows multiplied by 10.
  SparseMatrix<double> K0, K1, K2;
  shifted_tangent(problem, 5e-5, K0);
  shifted_tangent(problem, 1e-4, K1);
  shifted_tangent(problem, 1e-4, K2);
  for (unsigned int i = 0; i < n / 2; ++i)
    K2.diag_element(i) *= 10;
  Vector<double> b(n), x(n), y(n);
  for (auto &v : b)
    v = uniform(random);

  std::cout << "Sparse Cholesky, " << n << " unknowns" << std::endl;
  {
    solver::SparseCholesky cholesky;
    // Factorizes K, prints whether it is positive definite after @p what,
    // and checks the solve of K x = b with the factor.
    const auto factorize_and_solve = [&](const std::string          &what,
                                         const SparseMatrix<double> &K) {
      std::cout << "  " << what << ": " << cholesky.factorize(K) << std::endl;
      cholesky.vmult(x, b);
      testing::check_below("  relative residual",
                           relative_residual(K, x, b),
                           1e-12);
    };
    factorize_and_solve("positive definite", K0);
    const std::size_t values = cholesky.values_held();
    std::cout << "  factor values held: " << (values > 0) << std::endl;
    SparseDirectUMFPACK lu;
    lu.initialize(K0);
    lu.vmult(y, b);
    y -= x;
    testing::check_below("  difference to UMFPACK, relative",
                         y.l2_norm() / x.l2_norm(),
                         1e-10);
    factorize_and_solve("refactorized (far matrix), positive definite", K2);
    // As after a material edit: the factor goes, and the pattern's
    // ordering serves the next matrix.
    cholesky.drop_factor();
    std::cout << "  factor dropped, factor held: " << cholesky.factorized()
              << ", its values freed: " << (cholesky.values_held() == 0)
              << std::endl;
    factorize_and_solve("factorized again, positive definite", K0);
    std::cout << "  as many values held as before: "
              << (cholesky.values_held() == values) << std::endl;

    SparseMatrix<double> indefinite;
    indefinite.reinit(K0.get_sparsity_pattern());
    indefinite.copy_from(K0);
    indefinite.diag_element(n / 2) = -indefinite.diag_element(n / 2);
    std::cout << "  one diagonal entry negated, positive definite: "
              << cholesky.factorize(indefinite)
              << ", factor held: " << cholesky.factorized()
              << ", its values freed: " << (cholesky.values_held() == 0)
              << std::endl;
    factorize_and_solve("after the failure, positive definite", K0);
  }
  {
    // A tridiagonal matrix, which CHOLMOD factorizes simplicially: by
    // default as L D L^T, which fails only on a zero pivot, so the pivots
    // must be positive for it to pass. With 1.5 on the diagonal (and -1
    // beside it) the matrix is indefinite (eigenvalues 1.5 - 2 cos(k pi /
    // 21)) with a positive diagonal: its fourth pivot is negative.
    const unsigned int m = 20;
    SparsityPattern    pattern(m, m, 3);
    for (unsigned int i = 0; i < m; ++i)
      for (unsigned int j = (i > 0 ? i - 1 : 0); j < std::min(m, i + 2); ++j)
        pattern.add(i, j);
    pattern.compress();
    SparseMatrix<double> T(pattern);
    for (unsigned int i = 0; i < m; ++i)
      for (unsigned int j = (i > 0 ? i - 1 : 0); j < std::min(m, i + 2); ++j)
        T.set(i, j, i == j ? 2. : -1.);
    solver::SparseCholesky cholesky;
    std::cout << "Tridiagonal " << m << " x " << m
              << ", positive definite: " << cholesky.factorize(T);
    for (unsigned int i = 0; i < m; ++i)
      T.set(i, i, 1.5);
    std::cout << "; with 1.5 on the diagonal: " << cholesky.factorize(T)
              << ", factor held: " << cholesky.factorized()
              << ", its values freed: " << (cholesky.values_held() == 0)
              << std::endl;
    // The simplicial factor, its values freed, factorizes again.
    for (unsigned int i = 0; i < m; ++i)
      T.set(i, i, 2.);
    Vector<double> c(m), z(m);
    for (unsigned int i = 0; i < m; ++i)
      c(i) = 1. + i;
    std::cout << "  diagonal 2 again, positive definite: "
              << cholesky.factorize(T) << std::endl;
    cholesky.vmult(z, c);
    testing::check_below("  relative residual",
                         relative_residual(T, z, c),
                         1e-12);
    // CHOLMOD's pivot test passes a NaN pivot: the factorization must not.
    // (diag_element(), since deal.II's debug set() refuses a NaN)
    T.diag_element(m / 2) = std::numeric_limits<double>::quiet_NaN();
    std::cout << "  with a NaN on the diagonal: " << cholesky.factorize(T)
              << ", factor held: " << cholesky.factorized() << std::endl;
    // A matrix of another pattern (of the same size) is an error, not
    // values written past the analyzed structure.
    SparsityPattern full(m, m, m);
    for (unsigned int i = 0; i < m; ++i)
      for (unsigned int j = 0; j < m; ++j)
        full.add(i, j);
    full.compress();
    SparseMatrix<double> dense(full);
    for (unsigned int i = 0; i < m; ++i)
      dense.set(i, i, 1.);
    try
      {
        cholesky.factorize(dense);
        std::cout << "  another pattern: no error" << std::endl;
      }
    catch (const ExceptionBase &e)
      {
        std::cout << "  another pattern: " << message_of(e) << std::endl;
      }
  }

  std::cout << "cg-cholesky (Cholesky tolerance 1e-8, factorization cost 20)"
            << std::endl;
  {
    TimedSolver tested("set Type = cg-cholesky\n"
                       "set Cholesky tolerance = 1e-8\n"
                       "set Cholesky factorization cost = 20",
                       problem.discretization->dof_handler);

    solver::LinearSolver &linear_solver = tested.linear_solver;
    std::cout << "  method: " << linear_solver.method() << std::endl;

    const auto solve = [&](const std::string          &name,
                           const SparseMatrix<double> &K,
                           const double                bound) {
      const unsigned int iterations = linear_solver.solve(K, x, b);
      std::cout << "  " << name << ": " << iterations << " iteration"
                << (iterations == 1 ? "" : "s") << std::endl;
      testing::check_below("    relative residual",
                           relative_residual(K, x, b),
                           bound);
    };
    solve("first tangent, factorized", K0, 1e-12);
    solve("nearby tangent, old factor", K1, 1e-8);
    solve("far matrix, old factor fails, factorized", K2, 1e-12);

    SparseMatrix<double> indefinite;
    indefinite.reinit(K2.get_sparsity_pattern());
    indefinite.copy_from(K2);
    for (unsigned int i = 0; i < n; i += 7)
      indefinite.diag_element(i) = -indefinite.diag_element(i);
    solve("indefinite tangent, UMFPACK", indefinite, 1e-10);
    // While factorizations keep failing, the next 1, 2, 4, then 8 systems
    // go to UMFPACK at once (D); then a factorization is tried again, fails,
    // and UMFPACK solves the system (F). A system UMFPACK did not solve
    // would print '?'.
    const auto solve_indefinite = [&](const unsigned int n_systems) {
      std::string pattern;
      for (unsigned int i = 0; i < n_systems; ++i)
        {
          const unsigned int setups = linear_solver.preconditioner_setups();
          const unsigned int direct = linear_solver.direct_solves();
          linear_solver.solve(indefinite, x, b);
          pattern +=
            (linear_solver.direct_solves() == direct + 1 ?
               (linear_solver.preconditioner_setups() > setups ? 'F' : 'D') :
               '?');
        }
      return pattern;
    };
    std::cout << "  27 more indefinite systems: " << solve_indefinite(27)
              << std::endl;
    // Factorized so far: K0, K2, and the indefinite matrix 5 times (each
    // F, and once before the 27), which failed.
    std::cout << "  systems UMFPACK solved so far: "
              << linear_solver.direct_solves() << ", Cholesky factorizations: "
              << linear_solver.preconditioner_setups() << std::endl;
    // Then K1 is factorized (the indefinite matrix left no factor), and
    // K0 is solved by CG with that factor.
    solve("then K1, Cholesky factor of K1", K1, 1e-12);
    solve("K0 by CG with K1's factor", K0, 1e-8);
    // Matrices a little way from K1 toward the far one need more CG
    // iterations with K1's factor. The factorization counts as 20 of them:
    // a solve that needs more than the CG solves before it, but not more
    // than the average cost per solve with the factorization counted, keeps
    // the factor; one that needs more than that average makes the next
    // system be factorized at once, since it would likely need as many.
    const auto toward_far = [&](const double t) {
      SparseMatrix<double> K;
      K.reinit(K1.get_sparsity_pattern());
      K.copy_from(K1);
      K *= 1 - t;
      K.add(t, K2);
      return K;
    };
    const SparseMatrix<double> K4 = toward_far(0.002), K3 = toward_far(0.003);
    solve("0.2 % of the way from K1 to the far matrix, K1's factor", K4, 1e-8);
    solve("the same again, below the average (20 + 1 + 11 + 14) / 3, "
          "K1's factor",
          K4,
          1e-8);
    solve("0.3 % of the way, K1's factor", K3, 1e-8);
    solve("the same again, above the average (20 + 1 + 11 + 14 + 14 + 18) "
          "/ 5, factorized",
          K3,
          1e-12);
    // A factorization that succeeded ends the run of failures: the next
    // indefinite system is followed by one direct solve only. Factorized
    // since the 7 above: K1, K3, and the indefinite matrix twice.
    std::cout << "  4 indefinite systems after it: " << solve_indefinite(4)
              << ", Cholesky factorizations: "
              << linear_solver.preconditioner_setups() << std::endl;
  }

  // A singular system on which CG with an earlier factor fails, whose
  // factorization fails, and which UMFPACK cannot solve: the Failure that
  // reaches Newton counts the CG iterations spent on it (it counted none).
  {
    TimedSolver tested("set Type = cg-cholesky\n"
                       "set Cholesky factorization cost = 20",
                       problem.discretization->dof_handler);
    tested.linear_solver.solve(K0, x, b);
    // Row and column 0 of K2 set to zero, and b(0) nonzero: no solution.
    SparseMatrix<double> singular;
    singular.reinit(K2.get_sparsity_pattern());
    singular.copy_from(K2);
    for (unsigned int r = 0; r < n; ++r)
      for (auto entry = singular.begin(r); entry != singular.end(r); ++entry)
        if (r == 0 || entry->column() == 0)
          entry->value() = 0;
    try
      {
        tested.linear_solver.solve(singular, x, b);
        std::cout << "  singular system: solved" << std::endl;
      }
    catch (const solver::LinearSolver::Failure &failure)
      {
        std::cout << "  singular system: " << failure.what() << ", after "
                  << failure.iterations << " CG iterations" << std::endl;
      }
  }

  // auto above its direct solver limit is cg-amg; a CG that fails (here:
  // one iteration allowed) hands the system to UMFPACK, whose timer
  // section is entered after CG's is left (deal.II's debug library
  // checks it: the Debug run of scripts/setup.sh --test). On the block above,
  // multigrid is a single level, solved exactly (at most 2000 unknowns); this
  // tangent has more.
  std::cout << "auto with cg-amg, CG limited to 1 iteration" << std::endl;
  {
    testing::Problem     large(testing::cantilever("8, 8, 8", "0; 0; 0") + R"(
      subsection Layout
        set Type = random
      end)");
    const unsigned int   m = large.discretization->dof_handler.n_dofs();
    SparseMatrix<double> K;
    Vector<double>       x(m), b(m);
    shifted_tangent(large, 0, K);
    for (auto &v : b)
      v = uniform(random);
    TimedSolver tested("set Type = auto\n"
                       "set Direct solver limit = 0\n"
                       "set Maximum iterations = 1",
                       large.discretization->dof_handler);

    solver::LinearSolver &linear_solver = tested.linear_solver;
    std::cout << "  " << m << " unknowns, method: " << linear_solver.method()
              << ", iterations: " << linear_solver.solve(K, x, b)
              << " (CG's 1, then UMFPACK's 1), systems UMFPACK solved: "
              << linear_solver.direct_solves() << std::endl;
    testing::check_below("  relative residual",
                         relative_residual(K, x, b),
                         1e-10);

    // The next 10 systems go straight to UMFPACK (1 iteration each), the
    // 11th to CG again, which fails and hands it over (2 iterations).
    std::cout << "  next 11 systems, iterations:";
    for (unsigned int s = 0; s < 11; ++s)
      std::cout << " " << linear_solver.solve(K, x, b);
    std::cout << "; systems UMFPACK solved: " << linear_solver.direct_solves()
              << std::endl;

    // Above Direct fallback limit, CG's failure is the solve's.
    TimedSolver limited("set Type = auto\n"
                        "set Direct solver limit = 0\n"
                        "set Direct fallback limit = 1000\n"
                        "set Maximum iterations = 1",
                        large.discretization->dof_handler);
    try
      {
        limited.linear_solver.solve(K, x, b);
        std::cout << "  above Direct fallback limit = 1000: solved"
                  << std::endl;
      }
    catch (const solver::LinearSolver::Failure &failure)
      {
        std::cout << "  above Direct fallback limit = 1000: " << failure.what()
                  << ", systems UMFPACK solved: "
                  << limited.linear_solver.direct_solves() << std::endl;
      }
  }

  // cg-amg's near null space follows the shape: the stress-free tangent of
  // a bar turned rigidly by 90 degrees about its axis is the rest tangent
  // with every node's block rotated, so its CG iterations are the rest
  // tangent's when the multigrid hierarchy has the rigid body modes of the
  // turned shape (solve()'s configuration), more with those of the rest shape.
  std::cout << "cg-amg on a bar turned by 90 degrees" << std::endl;
  {
    testing::Problem      bar(testing::cantilever("6, 24, 6", "0; 0; 0"));
    const DoFHandler<3>  &dof_handler = bar.discretization->dof_handler;
    const unsigned int    m           = dof_handler.n_dofs();
    std::vector<Point<3>> points(m);
    DoFTools::map_dofs_to_support_points(MappingQ1<3>(), dof_handler, points);
    const std::vector<unsigned int> component =
      solver::dof_components(dof_handler);
    // About the axis x = z = 0.03 m: (x, z) -> (z, -x) about it.
    Vector<double> turned(m), at_rest(m), residual;
    for (unsigned int i = 0; i < m; ++i)
      {
        const double x = points[i][0] - 0.03, z = points[i][2] - 0.03;
        turned(i) = component[i] == 0 ? z - x : component[i] == 2 ? -x - z : 0;
      }
    // Unsupported (as the tangents of shifted_tangent()), shifted by 1e-4
    // of the mean diagonal: a shift keeps the turned tangent the rotated
    // rest tangent, and leaves the rigid motions as the near null space.
    SparseMatrix<double> K_rest, K_turned;
    bar.solver->residual_and_tangent(at_rest, 1., residual, K_rest);
    bar.solver->residual_and_tangent(turned, 1., residual, K_turned);
    double trace = 0;
    for (unsigned int i = 0; i < m; ++i)
      trace += K_rest.diag_element(i);
    for (SparseMatrix<double> *K : {&K_rest, &K_turned})
      for (unsigned int i = 0; i < m; ++i)
        K->diag_element(i) += 1e-4 * trace / m;
    Vector<double> x(m), b(m);
    for (auto &v : b)
      v = uniform(random);
    const auto iterations = [&](const SparseMatrix<double> &K,
                                const Vector<double>       *configuration) {
      TimedSolver        tested("set Type = cg-amg\nset Tolerance = 1e-8",
                         dof_handler);
      const unsigned int n_iterations =
        tested.linear_solver.solve(K, x, b, 1, configuration);
      AssertThrow(relative_residual(K, x, b) < 1e-8, ExcInternalError());
      return n_iterations;
    };
    const unsigned int at_rest_iterations    = iterations(K_rest, nullptr);
    const unsigned int turned_iterations     = iterations(K_turned, &turned);
    const unsigned int rest_modes_iterations = iterations(K_turned, nullptr);
    std::cout << "  " << m << " unknowns, CG iterations: at rest "
              << at_rest_iterations << "; turned, with the modes of the "
              << "turned shape " << turned_iterations
              << ", with those of the rest shape " << rest_modes_iterations
              << std::endl;

    // The rest tangent solved to 1e-2, 1e-6 and 1e-10 (the default
    // Tolerance, then tighter forcing terms) with the hierarchy of the first
    // solve; then the rest tangent shifted by its mean diagonal, for which
    // that hierarchy needs more iterations per decade, so the solve after
    // it builds a new hierarchy.
    std::cout << "cg-amg's multigrid hierarchy as the tolerance tightens"
              << std::endl;
    {
      TimedSolver tested("set Type = cg-amg", dof_handler);

      solver::LinearSolver &linear_solver = tested.linear_solver;
      for (const double forcing : {1e-2, 1e-6, 1e-10})
        {
          const unsigned int n = linear_solver.solve(K_rest, x, b, forcing);
          testing::check_below("  relative residual",
                               relative_residual(K_rest, x, b) / forcing,
                               1);
          std::cout << "  to " << forcing << ": " << n
                    << " CG iterations, multigrid builds: "
                    << linear_solver.preconditioner_setups() << std::endl;
        }
      SparseMatrix<double> K_shifted(K_rest.get_sparsity_pattern());
      K_shifted.copy_from(K_rest);
      for (unsigned int i = 0; i < m; ++i)
        K_shifted.diag_element(i) += trace / m;
      for (unsigned int k = 0; k < 2; ++k)
        {
          const unsigned int n = linear_solver.solve(K_shifted, x, b, 1e-10);
          std::cout << "  shifted tangent to 1e-10: " << n
                    << " CG iterations, multigrid builds: "
                    << linear_solver.preconditioner_setups() << std::endl;
        }

      // With at most 50 CG iterations the rest tangent's hierarchy fails on
      // the shifted tangent (137 above): the solve tries once more with a
      // hierarchy of its own (10 above) and counts both tries' iterations.
      TimedSolver limited("set Type = cg-amg\nset Maximum iterations = 50",
                          dof_handler);
      limited.linear_solver.solve(K_rest, x, b, 1e-10);
      const unsigned int n =
        limited.linear_solver.solve(K_shifted, x, b, 1e-10);
      testing::check_below("  relative residual",
                           relative_residual(K_shifted, x, b) / 1e-10,
                           1);
      std::cout << "  at most 50 CG iterations, shifted tangent to 1e-10 "
                   "after the rest tangent: "
                << n << " CG iterations, multigrid builds: "
                << limited.linear_solver.preconditioner_setups() << std::endl;
    }
  }
}
