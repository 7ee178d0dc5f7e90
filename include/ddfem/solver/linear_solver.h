#ifndef ddfem_solver_linear_solver_h
#define ddfem_solver_linear_solver_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <ddfem/solver/sparse_cholesky.h>

#include <string>
#include <vector>

namespace ddfem::solver
{
  using namespace dealii;

  /**
   * Solves the linearized systems K x = b of the Newton method with one of
   * - a sparse LU factorization of every system (UMFPACK, 'direct');
   * - conjugate gradients preconditioned by the sparse Cholesky factor of
   *   an earlier system ('cg-cholesky'): the factor is recomputed when the
   *   last solve needed more CG iterations than the average cost per solve
   *   since the last factorization (which counts as 'Cholesky
   *   factorization cost' iterations), or when CG needs more than that
   *   cost, so a few factorizations serve a whole load path; a system
   *   whose factorization finds it not positive definite goes to UMFPACK,
   *   and so do the next 1, 2, 4, then 8 solves while factorizations keep
   *   failing (Newton's retries of a shifted tangent count too). CG with an
   *   earlier factor does not test the system: an indefinite one may be
   *   solved so, and Newton's descent check rejects a direction that does
   *   not descend;
   * - conjugate gradients preconditioned by Trilinos ML algebraic multigrid
   *   whose near null space are the six rigid body modes ('cg-amg'). The
   *   hierarchy is kept across Newton iterations and rebuilt when CG
   *   needs 1.5 times the iterations per decade of residual reduction it
   *   needed right after the last rebuild, after a failed solve, and after
   *   reset(); a solve that fails with the hierarchy of an earlier tangent
   *   is tried once more with one of its own.
   * 'auto' picks cg-cholesky for small systems and cg-amg for large ones.
   * In 'auto' mode, a cg-amg failure on a system of moderate size switches
   * to the direct solver for a few systems.
   * Declared in the prm subsection "Linear solver".
   */
  class LinearSolver
  {
  public:
    /// Thrown when a solve fails (singular or indefinite matrix, no
    /// convergence); the Newton method reacts by regularizing.
    struct Failure : public std::runtime_error
    {
      /// A failure described by @p what, after @p iterations iterations.
      explicit Failure(const std::string &what,
                       const unsigned int iterations = 0)
        : std::runtime_error(what)
        , iterations(iterations)
      {}

      /// The iterations the failed solve spent (0 for the direct solver).
      unsigned int iterations;
    };

    /// Declares the subsection "Linear solver".
    static void
    declare_parameters(ParameterHandler &prm);

    /// Reads the subsection "Linear solver".
    void
    parse_parameters(ParameterHandler &prm);

    /**
     * Prepares for systems on @p dof_handler (an element of three
     * components, p <= 2, whose DoFs are numbered node by node, the three
     * components of a node consecutive: FE_Q(p)^3 as distributed,
     * FE_DGQ(p)^3 as dg::System renumbers it): chooses
     * the method ('auto' takes @p small_systems up to 'Direct solver
     * limit' unknowns, cg-amg above) and computes the rigid body modes for
     * the multigrid preconditioner. Throws ExcMessage naming Linear
     * solver/Type if cg-amg is chosen for an element without support
     * points (FE_DGP). @p timer receives the sections "factorization /
     * preconditioner" and "linear solve".
     */
    void
    initialize(const DoFHandler<3> &dof_handler,
               TimerOutput         &timer,
               const std::string   &small_systems = "cg-cholesky");

    /// Forgets the factor and the multigrid hierarchy of earlier tangents,
    /// as after a material edit or a finished solve, and frees their
    /// memory: the next solve builds them anew (a Cholesky factor keeps its
    /// ordering, since the sparsity pattern stays the same).
    void
    reset();

    /**
     * Solves @p K x = @p b. The iterative solver stops when the residual
     * is reduced by the factor min(@p forcing, 'Tolerance') (the forcing
     * term of an inexact Newton method; 'Cholesky tolerance' replaces
     * 'Tolerance' for cg-cholesky, and the direct solver ignores it).
     * Returns the number of iterations (1 for the direct solver). Throws
     * Failure if the solver does not succeed, std::bad_alloc if a
     * factorization runs out of memory, and std::runtime_error if CHOLMOD
     * fails otherwise (e.g. a factor too large for its 32-bit indices).
     *
     * @p configuration, if given, is the displacement u (of the DoFHandler
     * of initialize()) at which @p K is the tangent. A multigrid hierarchy
     * that cg-amg builds for @p K then has the rigid body modes of the
     * deformed shape X + u: a turned part's tangent is nearly singular on
     * rotations about its present place, not about its rest shape. Without
     * it, the rest shape serves.
     */
    unsigned int
    solve(const SparseMatrix<double> &K,
          Vector<double>             &x,
          const Vector<double>       &b,
          const double                forcing       = 1,
          const Vector<double>       *configuration = nullptr);

    /// Overrides 'Type' ("auto", "direct", "cg-cholesky" or "cg-amg") for
    /// the next initialize().
    void
    set_type(const std::string &type);

    /// The method in use: "direct", "cg-cholesky" or "cg-amg".
    const std::string &
    method() const
    {
      return chosen;
    }

    /// The systems UMFPACK solved since initialize(): every system with
    /// the method "direct", the fallbacks of the iterative methods (an
    /// indefinite tangent for cg-cholesky, a CG failure for 'auto') and
    /// the systems after them otherwise.
    unsigned int
    direct_solves() const
    {
      return n_direct_solves;
    }

    /// The preconditioners set up since initialize(): multigrid
    /// hierarchies with the method cg-amg, Cholesky factorizations with
    /// cg-cholesky (those that found the tangent indefinite included).
    unsigned int
    preconditioner_setups() const
    {
      return n_preconditioner_setups;
    }

  private:
    /// UMFPACK; throws Failure if the matrix is singular.
    unsigned int
    solve_directly(const SparseMatrix<double> &K,
                   Vector<double>             &x,
                   const Vector<double>       &b);

    /**
     * solve_directly(), and the @p next solves too: called where the
     * iterative solver cannot handle a tangent (cg-amg failed, or the
     * tangent is indefinite for cg-cholesky), since the tangents that
     * follow are likely as hard. Returns the iterations with the @p spent
     * ones of the iterative solver added; a Failure of the direct solver
     * carries them too.
     */
    unsigned int
    fall_back_to_direct(const SparseMatrix<double> &K,
                        Vector<double>             &x,
                        const Vector<double>       &b,
                        const unsigned int          next,
                        const unsigned int          spent);

    /// 'Type' as given, and the method it resolved to for this system.
    std::string requested, chosen;
    /// cg-cholesky: CG with the last Cholesky factor, or a new factor if
    /// there is none, if the last solve needed more iterations than the
    /// average cost per solve of the factor so far, or if CG needs more
    /// than 'Cholesky factorization cost' iterations.
    unsigned int
    solve_with_cholesky(const SparseMatrix<double> &K,
                        Vector<double>             &x,
                        const Vector<double>       &b,
                        const double                forcing);

    /// 'Tolerance', 'Cholesky tolerance', 'Cholesky factorization cost',
    /// 'Maximum iterations', 'Direct solver limit' and 'Direct fallback
    /// limit'.
    double       tolerance, cholesky_tolerance;
    unsigned int factorization_cost, max_iterations, direct_limit,
      fallback_limit;
    /// Systems still to be solved directly after a cg-amg failure ('auto')
    /// or an indefinite tangent (cg-cholesky).
    unsigned int direct_solves_left = 0;
    /// 'auto': the solves that go to UMFPACK after CG failed (cg-cholesky
    /// instead backs off by the factorizations that failed in a row: a
    /// failed factorization costs less than a failed CG run).
    static constexpr unsigned int direct_solves_after_cg_failure = 10;
    /// cg-cholesky: factorizations in a row that found the tangent
    /// indefinite.
    unsigned int indefinite_factors = 0;
    /// What direct_solves() and preconditioner_setups() return.
    unsigned int n_direct_solves = 0, n_preconditioner_setups = 0;
    /// Polynomial degree of the element (for the AMG settings).
    unsigned int degree = 1;
    /// Receives the solver's timing sections.
    TimerOutput *timer = nullptr;

    /// CG iterations of the last solve (1 for the exact solve with a new
    /// Cholesky factor).
    unsigned int last_iterations = 0;
    /// cg-amg: CG iterations per decade of residual reduction of the
    /// first solve with the current multigrid hierarchy (0: build a new
    /// one), and of the last solve.
    double rate_after_setup = 0, last_rate = 0;
    /// cg-cholesky: the solves with the current factor, and their cost in
    /// CG iterations, its factorization included.
    unsigned int solves_with_factor = 0, cost_with_factor = 0;

    /// cg-amg: fills rigid_body_modes for the shape support_points +
    /// @p configuration (the rest shape if null).
    void
    compute_rigid_body_modes(const Vector<double> *configuration);

    /// cg-amg: every DoF's support point in the rest shape and component.
    std::vector<Point<3>>     support_points;
    std::vector<unsigned int> components;
    /// The six rigid body modes, mode-major (mode k at [k * n_dofs]).
    std::vector<double> rigid_body_modes;

    /// The Cholesky factor of cg-cholesky, the Trilinos copy of the
    /// matrix the multigrid hierarchy was built from, and that hierarchy.
    SparseCholesky                    cholesky;
    TrilinosWrappers::SparseMatrix    trilinos_matrix;
    TrilinosWrappers::PreconditionAMG amg;
  };
} // namespace ddfem::solver

#endif
