#ifndef ddfem_solver_static_solver_h
#define ddfem_solver_static_solver_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <ddfem/scene/boundary_conditions.h>
#include <ddfem/solver/discretization.h>
#include <ddfem/solver/linear_solver.h>

#include <functional>
#include <string>
#include <vector>

namespace ddfem::solver
{
  using namespace dealii;

  /**
   * The load factors of a load-stepped solve: increments of the nominal
   * 1 / (load steps) from 0 up to 1 (the last one shortened to reach 1),
   * an increment that fails halved, and the increment doubled back toward
   * the nominal after two that succeed.
   */
  class LoadSteps
  {
  public:
    /// Steps of 1 / @p n_steps; cut() fails below @p minimum_step of that.
    LoadSteps(const unsigned int n_steps, const double minimum_step);

    /// Whether the load factor reached 1.
    bool
    done() const;

    /// The load factor reached.
    double
    current() const;

    /// The load factor the next increment goes to, at most 1.
    double
    next() const;

    /// The next increment succeeded: current() becomes next().
    void
    accept();

    /**
     * The next increment failed: halves it (the increment tried, which is
     * shorter than the step where it ends at 1), and returns whether the
     * half is at least the minimum step.
     */
    bool
    cut();

    /// Whether the increment is shorter than the nominal one after a cut
    /// (the last increment, to 1, may be shorter without one).
    bool
    is_cut() const;

  private:
    double       nominal_step, minimum, t, step;
    unsigned int successes_since_cut = 0;
  };

  /**
   * Quasi-static hyperelastic equilibrium on a Discretization: minimizes
   * the total potential energy
   *
   *   E(u) = sum_cells int psi(F) dV - t f_ext . u
   *
   * for load factors t stepping from 0 to 1, by Newton's method with a
   * backtracking line search on E (the DDFEM paper's Algorithm 1). States
   * with det F <= 0 anywhere have infinite energy and are never accepted.
   * Non-descent Newton directions (indefinite tangents, e.g. in buckling)
   * and failed linear solves are handled by shifting the tangent by a
   * growing multiple of its diagonal; load increments whose Newton
   * iteration fails are cut in half. Each increment starts from the last
   * state extrapolated along the last increment (a line) or the last two
   * (a parabola), whichever has the lower energy. After a material edit,
   * Newton's method first tries the full load from the last equilibrium.
   */
  class StaticSolver
  {
  public:
    /// Parameters of the subsection "Nonlinear solver".
    struct Parameters
    {
      /// Declares the subsection "Nonlinear solver".
      static void
      declare_parameters(ParameterHandler &prm);
      /// Reads the subsection "Nonlinear solver".
      void
      parse_parameters(ParameterHandler &prm);

      /// Nominal number of equal load increments.
      unsigned int load_steps = 10;
      /// Smallest load increment, as a fraction of the nominal one, before
      /// the solver gives up.
      double minimum_step = 1e-3;
      /// Newton iterations per load increment before it counts as failed.
      unsigned int max_iterations = 30;
      /// Relative residual tolerance of Newton's method.
      double tolerance = 1e-8;
      /// Whether a solve after a converged one (after a material edit)
      /// starts with Newton's method at the full load from that solve's
      /// state, before it steps the load from rest.
      bool start_from_last_state = true;
    };

    /// What a solve did.
    struct Statistics
    {
      /// Whether the full load (t = 1) was reached.
      bool converged = false;
      /// Whether the full load was reached from the last solve's state
      /// (Parameters::start_from_last_state), in one increment.
      bool from_last_state = false;
      /// Accepted load increments.
      unsigned int load_steps = 0;
      /// Load increments that failed and were retried with half the step
      /// (the failure that ends a solve is not a cut).
      unsigned int step_cuts = 0;
      /// Newton iterations over all load increments (failed ones included,
      /// and a failed start from the last state).
      unsigned int newton_iterations = 0;
      /// Newton iterations of a start from the last state that failed,
      /// before the load steps from rest.
      unsigned int failed_start_iterations = 0;
      /// Linear solver iterations over all Newton iterations.
      unsigned int linear_iterations = 0;
      /// Linear systems UMFPACK solved (LinearSolver::direct_solves()):
      /// all of them with the direct solver, the fallbacks of the iterative
      /// solvers otherwise.
      unsigned int direct_solves = 0;
      /// Preconditioners the iterative solver set up
      /// (LinearSolver::preconditioner_setups()): multigrid hierarchies
      /// for cg-amg, Cholesky factorizations for cg-cholesky (those that
      /// found the tangent indefinite included).
      unsigned int preconditioner_setups = 0;
      /// Newton iterations that needed a regularized tangent.
      unsigned int regularized_iterations = 0;
      /// Smallest det F at any quadrature point in the final state.
      double min_J = 1;
      /// Smallest det F at a corner of a solid voxel in the final state
      /// (smallest_vertex_jacobian()).
      double min_vertex_J = 1;
      /// Why the solve stopped early (empty if converged).
      std::string failure;

      /// How the solve went: "after L load steps and N Newton iterations"
      /// or "from the last state after N Newton iterations", with the
      /// iterations of a failed start from the last state named.
      std::string
      describe() const;
    };

    /// Per-cell results for output.
    struct CellFields
    {
      /// det F of each active cell, averaged over its quadrature points
      /// with the rule's weights (at the points of a coarse rule, not the
      /// volume average).
      Vector<double> J;
      /// von Mises Cauchy stress of each active cell (Pa), averaged as J.
      Vector<double> von_mises;
      /// Largest material::principal_strain at any quadrature point of each
      /// active cell.
      Vector<double> strain;
    };

    /**
     * A solver for @p discretization under @p boundary_conditions. The
     * objects passed must outlive the solver. @p timer receives the
     * sections "assembly" and "line search" (and the linear solver's).
     * Throws ExcMessage if a rotation turns by more than 90 degrees per
     * load step (BoundaryConditions::check_rotation_steps()).
     */
    StaticSolver(const Discretization            &discretization,
                 const scene::BoundaryConditions &boundary_conditions,
                 const Parameters                &parameters,
                 LinearSolver                    &linear_solver,
                 TimerOutput                     &timer,
                 ConditionalOStream              &pcout);

    /**
     * Finds the Dirichlet nodes, assembles the external load vector,
     * builds the sparsity pattern and checks that the Dirichlet conditions
     * remove all rigid body motions of every connected part of the solid.
     * Throws ExcMessage describing the problem otherwise (no Dirichlet
     * condition, floating voxels, parts joined only along an edge or at a
     * corner).
     */
    void
    setup();

    /**
     * Takes the materials of the discretization's points as they are now,
     * after a material edit that keeps the solid's voxels (the Dirichlet
     * nodes, the sparsity and the loads stay those of setup()): the scale
     * of the energy's round-off, and a linear solver without the factors
     * of the old materials' tangents.
     */
    void
    update_materials();

    /**
     * Steps the load factor from 0 to 1. After each accepted increment,
     * calls @p on_step with the increment's number (from 1) and its load
     * factor. If the last solve reached the full load and
     * Parameters::start_from_last_state is set, Newton's method first
     * tries the full load from that state (one increment, to load factor
     * 1), and the load steps from rest follow only if it fails: after a
     * material edit the new equilibrium is usually near the old one.
     * The linear solver's factors and multigrid hierarchy are freed at
     * the end, also when an exception ends it: the next solve follows an
     * edit, which makes them stale.
     */
    Statistics
    solve(const std::function<void(unsigned int, double)> &on_step);

    /// The displacement (m) of the last accepted state.
    const Vector<double> &
    solution() const
    {
      return displacement;
    }

    /// Total potential energy E(@p u) at load factor @p t (J); +infinity if
    /// det F <= 0 anywhere.
    double
    energy(const Vector<double> &u, const double t) const;

    /**
     * The unconstrained gradient dE/du (@p residual) and Hessian
     * (@p tangent, reinitialized on the tangent's sparsity pattern without
     * constraints) at @p u and load factor @p t. For verification.
     */
    void
    residual_and_tangent(const Vector<double> &u,
                         const double          t,
                         Vector<double>       &residual,
                         SparseMatrix<double> &tangent) const;

    /// Per-cell det F, von Mises stress and largest principal strain of
    /// the state @p u (see CellFields).
    CellFields
    cell_fields(const Vector<double> &u) const;

    /**
     * The smallest det F of the state @p u at the corners of the solid
     * voxels (of a coarse cell's block: its vertices and the points
     * between them), and that corner. Where it is not positive, a cell is
     * turned inside out there although det F may be positive at every
     * quadrature point. Of corners with values equal up to round-off, the
     * first in cell order (FirstSmallest).
     */
    std::pair<double, Point<3>>
    smallest_vertex_jacobian(const Vector<double> &u) const;

    /// The displacement at point @p p of the state @p u (throws if @p p
    /// lies outside the solid).
    Tensor<1, 3>
    point_value(const Vector<double> &u, const Point<3> &p) const;

  private:
    /**
     * One pass over all cells: energy always, the raw gradient into
     * @p residual if non-null, and the tangent and Newton right hand side
     * condensed with @p constraints if @p tangent is non-null. Returns the
     * total potential energy (+infinity if inadmissible); sets @p min_J.
     */
    double
    assemble(const Vector<double>            &u,
             const double                     t,
             Vector<double>                  *residual,
             const AffineConstraints<double> *constraints,
             SparseMatrix<double>            *tangent,
             Vector<double>                  *newton_rhs,
             double                          &min_J) const;

    /// solve() up to freeing the linear solver's memory.
    Statistics
    solve_load_path(const std::function<void(unsigned int, double)> &on_step);

    /// Newton's method at load factor @p t starting from @p u. Returns
    /// false, and says why in newton_failure, if it stops unconverged.
    bool
    newton(const double t, Vector<double> &u, Statistics &statistics);

    /**
     * newton(), and the test of the state it converged to: returns true if
     * @p u is an equilibrium at load factor @p t with det F > 0 at every
     * vertex of a solid voxel (statistics.min_vertex_J is then that
     * state's). Otherwise returns false, and @p inverted says where a
     * converged state turns a cell inside out (empty if Newton's method
     * failed).
     */
    bool
    converge(const double    t,
             Vector<double> &u,
             Statistics     &statistics,
             std::string    &inverted);

    /// Makes @p u (swapped out) the accepted state at load factor @p t:
    /// counts the increment and calls @p on_step.
    void
    accept(Vector<double>                                  &u,
           const double                                     t,
           Statistics                                      &statistics,
           const std::function<void(unsigned int, double)> &on_step);

    /// Throws if the Dirichlet nodes leave rigid motions free (see setup()).
    void
    check_supports() const;

    const Discretization            &discretization;
    const scene::BoundaryConditions &boundary_conditions;
    const Parameters                 parameters;
    LinearSolver                    &linear_solver;
    TimerOutput                     &timer;
    ConditionalOStream              &pcout;

    /// Dirichlet degrees of freedom with their support point and component.
    struct DirichletDof
    {
      types::global_dof_index index;
      Point<3>                point;
      unsigned int            component;
    };
    std::vector<DirichletDof> dirichlet_dofs;

    /// Newton iterations with a shifted tangent a load increment may take
    /// before it counts as failed.
    static constexpr unsigned int max_regularized_iterations = 8;

    /// Sum over quadrature points of (mu + |lambda| + C) dV (J): the scale
    /// of round-off errors in the total energy.
    double stiffness_volume = 0;

    /// Sparsity of the tangent, without constraints.
    SparsityPattern pattern;
    /// The condensed Newton matrix (tangent with Dirichlet rows).
    SparseMatrix<double> system_matrix;
    /// Dead external loads at t = 1 (body force and tractions, N).
    Vector<double> external_force;
    /// The last accepted state (m).
    Vector<double> displacement;
    /// Whether #displacement is an equilibrium at the full load, of the
    /// materials of the last solve.
    bool at_full_load = false;
    /// Why the last call of newton() stopped unconverged, for the message
    /// of a solve that fails (which parameter to change).
    std::string newton_failure;
  };
} // namespace ddfem::solver

#endif
