#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/sparse_direct.h>

#include <Teuchos_ParameterList.hpp>
#include <ddfem/base/statistics.h>
#include <ddfem/solver/linear_solver.h>
#include <ddfem/solver/supports.h>

#include <cmath>
#include <new>
#include <string>

namespace ddfem::solver
{
  namespace
  {
    // The smallest relative residual reduction a CG solve is asked for.
    constexpr double smallest_reduction = 1e-12;

    // The decades of residual reduction a CG solve with @p tolerance is
    // asked for, at least one.
    double
    decades(const double tolerance)
    {
      return std::max(1., -std::log10(std::max(smallest_reduction, tolerance)));
    }

    // CG from x = 0 until the residual is at most tolerance |b|, but not
    // below smallest_reduction |b|. Returns the iterations; throws
    // SolverControl::NoConvergence after max_iterations.
    template <typename Preconditioner>
    unsigned int
    solve_with_cg(const SparseMatrix<double> &K,
                  Vector<double>             &x,
                  const Vector<double>       &b,
                  const Preconditioner       &preconditioner,
                  const unsigned int          max_iterations,
                  const double                tolerance)
    {
      SolverControl            control(max_iterations,
                            std::max(smallest_reduction, tolerance) *
                              b.l2_norm());
      SolverCG<Vector<double>> cg(control);
      x = 0;
      cg.solve(K, x, b, preconditioner);
      return control.last_step();
    }
  } // namespace



  void
  LinearSolver::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Linear solver");
    prm.declare_entry(
      "Type",
      "auto",
      Patterns::Selection("auto|direct|cg-cholesky|cg-amg"),
      "direct: UMFPACK sparse LU of every tangent. cg-cholesky: conjugate "
      "gradients preconditioned by the CHOLMOD Cholesky factor of an "
      "earlier tangent, refactorized when the CG iterations grow (see "
      "'Cholesky factorization cost'; UMFPACK for a tangent that is not "
      "positive definite, and the next 1, 2, 4 or 8 solves while "
      "factorizations keep failing). cg-amg: conjugate "
      "gradients with "
      "Trilinos ML algebraic multigrid (rigid body modes as near null "
      "space). auto: cg-cholesky up to 'Direct solver limit' unknowns, "
      "cg-amg above (Method = dg: direct up to the limit, since the "
      "corotated iteration needs exact solves at high stiffness "
      "contrast; a linear DG system whose definiteness check passed is "
      "solved with the check's Cholesky factor, whatever the type).");
    prm.declare_entry(
      "Tolerance",
      "1e-2",
      Patterns::Double(1e-12, 0.5),
      "cg-amg: the loosest relative residual reduction of a linear solve "
      "(at most 0.5: at 1, the first solve of a load step, which lifts the "
      "part to its new boundary values, would do nothing). "
      "Newton's method tightens it to 0.1 |R| / |R_ref| as its residual "
      "|R| falls (inexact Newton), so early iterations are cheap and the "
      "last ones accurate. Method = dg solves to 1e-12.");
    prm.declare_entry(
      "Cholesky tolerance",
      "1e-8",
      Patterns::Double(1e-12, 0.5),
      "cg-cholesky: the loosest relative residual reduction of a linear "
      "solve (tightened like 'Tolerance', at most 0.5 like it). Its iterations are cheap, so "
      "tight solves that keep Newton's quadratic convergence pay off. "
      "Method = dg solves to 1e-12.");
    prm.declare_entry(
      "Cholesky factorization cost",
      "40",
      Patterns::Integer(1),
      "cg-cholesky: the time of a factorization, counted in CG iterations "
      "with the factor (30 to 100 measured on models of 1275 to 329967 "
      "unknowns). The current tangent is factorized when the last solve "
      "needed more iterations than the average cost per solve since the "
      "last factorization (that factorization included), or when a "
      "solve with the old factor would need more than this many.");
    prm.declare_entry("Maximum iterations",
                      "500",
                      Patterns::Integer(1),
                      "cg-amg: iterations before a solve counts as failed.");
    prm.declare_entry(
      "Direct solver limit",
      "30000",
      Patterns::Integer(0),
      "auto: largest number of unknowns solved with cg-cholesky (with the "
      "direct solver for Method = dg). Above about 30000 unknowns, "
      "multigrid is as fast or faster, and the factor's memory grows "
      "quickly.");
    prm.declare_entry(
      "Direct fallback limit",
      "150000",
      Patterns::Integer(0),
      "auto: when CG fails (an indefinite tangent near buckling, "
      "say) on a system of at most this many unknowns, that and "
      "the next 10 solves are direct.");
    prm.leave_subsection();
  }



  void
  LinearSolver::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Linear solver");
    requested          = prm.get("Type");
    tolerance          = prm.get_double("Tolerance");
    cholesky_tolerance = prm.get_double("Cholesky tolerance");
    factorization_cost = prm.get_integer("Cholesky factorization cost");
    max_iterations     = prm.get_integer("Maximum iterations");
    direct_limit       = prm.get_integer("Direct solver limit");
    fallback_limit     = prm.get_integer("Direct fallback limit");
    prm.leave_subsection();
  }



  void
  LinearSolver::set_type(const std::string &type)
  {
    Assert(type == "auto" || type == "direct" || type == "cg-cholesky" ||
             type == "cg-amg",
           ExcMessage("Unknown linear solver type " + type));
    requested = type;
  }



  void
  LinearSolver::initialize(const DoFHandler<3> &dof_handler,
                           TimerOutput         &timer_output,
                           const std::string   &small_systems)
  {
    timer                           = &timer_output;
    const types::global_dof_index n = dof_handler.n_dofs();
    chosen                          = requested;
    if (requested == "auto")
      chosen = (n <= direct_limit) ? small_systems : "cg-amg";
    degree = dof_handler.get_fe().degree;
    cholesky.clear();
    reset();
    n_direct_solves         = 0;
    n_preconditioner_setups = 0;
    if (chosen != "cg-amg")
      return;
    AssertThrow(dof_handler.get_fe().has_support_points(),
                ExcMessage("Linear solver/Type = cg-amg (or auto, which "
                           "picks it above 'Direct solver limit' unknowns) "
                           "builds its rigid body modes from the element's "
                           "support points, and " +
                           dof_handler.get_fe().get_name() +
                           " has none: use Type = cg-cholesky or direct."));

    support_points.resize(n);
    DoFTools::map_dofs_to_support_points(MappingQ1<3>(),
                                         dof_handler,
                                         support_points);
    components = dof_components(dof_handler);
    for (std::size_t i = 0; i < n; ++i)
      Assert(i >= components[i] &&
               support_points[i - components[i]] == support_points[i],
             ExcMessage("The three DoFs of a node must be consecutive."));
  }



  void
  LinearSolver::compute_rigid_body_modes(const Vector<double> *configuration)
  {
    // About the centroid of the support points where they are now; the
    // three DoFs of a node are consecutive (initialize()).
    const std::size_t     n = support_points.size();
    std::vector<Point<3>> points(support_points);
    if (configuration != nullptr)
      {
        AssertDimension(configuration->size(), n);
        for (std::size_t i = 0; i < n; ++i)
          for (unsigned int d = 0; d < 3; ++d)
            points[i][d] += (*configuration)(i - components[i] + d);
      }
    Point<3> centroid;
    for (const Point<3> &p : points)
      centroid += p / static_cast<double>(n);
    rigid_body_modes.resize(6 * n);
    for (std::size_t i = 0; i < n; ++i)
      {
        const std::array<double, 6> modes =
          solver::rigid_body_modes(points[i] - centroid, components[i]);
        for (unsigned int m = 0; m < 6; ++m)
          rigid_body_modes[m * n + i] = modes[m];
      }
  }



  void
  LinearSolver::reset()
  {
    rate_after_setup   = 0;
    direct_solves_left = 0;
    indefinite_factors = 0;
    cholesky.drop_factor();
    amg.clear();
    trilinos_matrix.clear();
  }



  unsigned int
  LinearSolver::fall_back_to_direct(const SparseMatrix<double> &K,
                                    Vector<double>             &x,
                                    const Vector<double>       &b,
                                    const unsigned int          next,
                                    const unsigned int          spent)
  {
    direct_solves_left = next;
    try
      {
        return spent + solve_directly(K, x, b);
      }
    catch (Failure &failure)
      {
        failure.iterations += spent;
        throw;
      }
  }



  unsigned int
  LinearSolver::solve_directly(const SparseMatrix<double> &K,
                               Vector<double>             &x,
                               const Vector<double>       &b)
  {
    // Every direct solve factorizes its matrix anew: the factor is freed
    // on return.
    SparseDirectUMFPACK direct;
    try
      {
        {
          TimerOutput::Scope scope(*timer, "factorization / preconditioner");
          direct.initialize(K);
        }
        TimerOutput::Scope scope(*timer, "linear solve");
        direct.vmult(x, b);
      }
    catch (const SparseDirectUMFPACK::ExcUMFPACKError &error)
      {
        // Status -1 is UMFPACK_ERROR_out_of_memory, which no shift of the
        // tangent cures; the other statuses mean a singular matrix.
        if (std::string(error.what()).find("error status -1.") !=
            std::string::npos)
          throw std::bad_alloc();
        throw Failure("the direct solver failed (singular matrix?)");
      }
    if (!all_finite(x))
      throw Failure(
        "the direct solver returned non-finite values (a singular matrix, or "
        "a load too large for it?)");
    ++n_direct_solves;
    return 1;
  }



  unsigned int
  LinearSolver::solve_with_cholesky(const SparseMatrix<double> &K,
                                    Vector<double>             &x,
                                    const Vector<double>       &b,
                                    const double                forcing)
  {
    // CG with the factor of an earlier tangent. Its iteration counts grow
    // as the state moves away from that tangent's, so the average cost per
    // solve since the factorization, F + (iterations), divided by the
    // solves, falls to a minimum and then rises. It starts rising when a
    // solve needs more iterations than the average so far: refactorize
    // when the last one did (the next is likely to need as many).
    unsigned int iterations = 0;
    if (cholesky.factorized() &&
        last_iterations * solves_with_factor <= cost_with_factor)
      {
        TimerOutput::Scope scope(*timer, "linear solve");
        try
          {
            last_iterations =
              solve_with_cg(K,
                            x,
                            b,
                            cholesky,
                            factorization_cost,
                            std::min(forcing, cholesky_tolerance));
            ++solves_with_factor;
            cost_with_factor += last_iterations;
            return last_iterations;
          }
        catch (const SolverControl::NoConvergence &failure)
          {
            iterations = failure.last_step;
          }
      }

    bool positive_definite;
    {
      TimerOutput::Scope scope(*timer, "factorization / preconditioner");
      positive_definite = cholesky.factorize(K);
      ++n_preconditioner_setups;
    }
    // An indefinite tangent (past a bifurcation, or in the first Newton
    // iterations after a large material edit). The next 1, 2, 4, then 8
    // solves are direct while factorizations keep failing: past a
    // bifurcation tangents stay indefinite for many iterations, after an
    // edit for a few.
    if (!positive_definite)
      {
        const unsigned int next = 1u << std::min(indefinite_factors++, 3u);
        return fall_back_to_direct(K, x, b, next, iterations);
      }
    indefinite_factors = 0;
    TimerOutput::Scope scope(*timer, "linear solve");
    cholesky.vmult(x, b);
    last_iterations    = 1;
    solves_with_factor = 1;
    cost_with_factor   = factorization_cost + 1;
    // A positive definite tangent can still be too soft for its load in
    // double precision: the solution overflows (UMFPACK's is checked alike).
    // The factor goes too: as CG's preconditioner for the shifted tangent
    // it would overflow again, which deal.II's debug library aborts on.
    if (!all_finite(x))
      {
        cholesky.drop_factor();
        throw Failure("the sparse Cholesky solve returned non-finite values "
                      "(a load too large for the tangent?)",
                      iterations);
      }
    return iterations + 1;
  }



  unsigned int
  LinearSolver::solve(const SparseMatrix<double> &K,
                      Vector<double>             &x,
                      const Vector<double>       &b,
                      const double                forcing,
                      const Vector<double>       *configuration)
  {
    if (chosen == "direct" || direct_solves_left > 0)
      {
        if (direct_solves_left > 0)
          --direct_solves_left;
        return solve_directly(K, x, b);
      }
    if (chosen == "cg-cholesky")
      return solve_with_cholesky(K, x, b, forcing);

    // The multigrid hierarchy of an earlier tangent stays a good
    // preconditioner while CG needs at most 1.5 times the iterations per
    // decade of residual reduction it needed right after the hierarchy was
    // built. Per decade, since inexact Newton asks its last solves for
    // more decades than its first, which costs iterations with any
    // preconditioner.
    bool rebuild =
      (rate_after_setup == 0 || 2 * last_rate > 3 * rate_after_setup);
    const double reduction        = std::min(forcing, tolerance);
    unsigned int stale_iterations = 0;
    while (true)
      {
        if (rebuild)
          {
            TimerOutput::Scope scope(*timer, "factorization / preconditioner");
            amg.clear(); // it refers to the matrix about to be replaced
            trilinos_matrix.reinit(K);
            compute_rigid_body_modes(configuration);
            TrilinosWrappers::PreconditionAMG::AdditionalData data;
            data.elliptic              = true;
            data.higher_order_elements = (degree > 1);
            data.smoother_sweeps       = 2;
            data.aggregation_threshold = 1e-4;
            Teuchos::ParameterList              list;
            std::unique_ptr<Epetra_MultiVector> unused_modes;
            data.set_parameters(list, unused_modes, trilinos_matrix);
            list.set("PDE equations", 3);
            list.set("null space: type", "pre-computed");
            list.set("null space: dimension", 6);
            list.set("null space: vectors", rigid_body_modes.data());
            amg.initialize(trilinos_matrix, list);
            ++n_preconditioner_setups;
          }
        try
          {
            // Closed before a fallback to the direct solver times its own.
            TimerOutput::Scope scope(*timer, "linear solve");
            last_iterations =
              solve_with_cg(K, x, b, amg, max_iterations, reduction);
            break;
          }
        catch (const SolverControl::NoConvergence &failure)
          {
            rate_after_setup = 0;
            // The hierarchy of an earlier tangent may be what failed, not
            // this tangent: one more try with a hierarchy of its own.
            if (!rebuild)
              {
                rebuild          = true;
                stale_iterations = failure.last_step;
                continue;
              }
            const unsigned int iterations =
              stale_iterations + failure.last_step;
            if (requested == "auto" && x.size() <= fallback_limit)
              return fall_back_to_direct(
                K, x, b, direct_solves_after_cg_failure, iterations);
            throw Failure(
              failure.last_step < max_iterations ?
                "CG stopped at iteration " + std::to_string(failure.last_step) +
                  " on a residual that is not finite" :
                "CG did not converge in Linear solver/Maximum iterations = " +
                  std::to_string(max_iterations) +
                  " (an indefinite or ill-conditioned tangent?)",
              iterations);
          }
      }
    const double n_decades = decades(reduction);
    last_rate              = last_iterations / n_decades;
    if (rebuild)
      rate_after_setup = std::max(1u, last_iterations) / n_decades;
    return stale_iterations + last_iterations;
  }
} // namespace ddfem::solver
