#ifndef ddfem_dg_system_h
#define ddfem_dg_system_h

#include <deal.II/base/function.h>
#include <deal.II/base/geometry_info.h>
#include <deal.II/base/point.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <ddfem/dg/parameters.h>
#include <ddfem/solver/sparse_cholesky.h>

#include <cmath>
#include <functional>
#include <vector>

namespace ddfem::dg
{
  using namespace dealii;

  /**
   * Whether the point @p unit_point of the reference cell lies on its face
   * @p f: the support points that strong Dirichlet conditions constrain
   * where they are asked at boundary faces only (System::make_constraints()
   * without ProblemData::dirichlet_inside).
   */
  template <int dim>
  inline bool
  on_unit_face(const Point<dim> &unit_point, const unsigned int f)
  {
    return std::abs(unit_point[GeometryInfo<dim>::unit_normal_direction[f]] -
                    f % 2) < 1e-12;
  }

  /**
   * The linear material of one cell. For a vector field (dim components):
   * the Lame parameters mu and lambda (Pa) of sigma = 2 mu eps + lambda
   * tr(eps) I. For a scalar field (one component, the Poisson problem):
   * sigma = mu grad u, lambda unused.
   */
  struct CellMaterial
  {
    /// Shear modulus (Pa), or the conductivity of a scalar problem.
    double mu = 1;
    /// Lame's first parameter (Pa).
    double lambda = 0;
  };

  /**
   * What the discrete problem is, independent of the discretization: the
   * material of every cell and the data of the boundary value problem.
   * Loads are given at load factor 1 and scaled by the load factor t;
   * component c of a load vector acts on component c of the field (a
   * scalar problem uses component 0).
   */
  template <int dim>
  struct ProblemData
  {
    /// Material per cell, indexed by active_cell_index().
    std::vector<CellMaterial> materials;
    /// Body force per volume at t = 1 at a point; empty: none.
    std::function<Tensor<1, dim>(const Point<dim> &)> body_force;
    /**
     * Surface load at t = 1 on a boundary face with the given center, at
     * a point with the given outward unit normal; empty: none.
     */
    std::function<Tensor<1, dim>(const Point<dim> &,
                                 const Point<dim> &,
                                 const Tensor<1, dim> &)>
      traction;
    /**
     * Dirichlet data: whether component c is prescribed at a point at load
     * factor t, and if so its value (written to the last argument). Empty:
     * no Dirichlet condition.
     */
    std::function<bool(const Point<dim> &, unsigned int, double, double &)>
      dirichlet;
    /**
     * Where dirichlet() is asked. False: at boundary faces only (its data
     * may then be given everywhere, as a manufactured solution's is). True:
     * inside the domain too, as CG holds every node of a region: strong
     * conditions constrain every node where dirichlet() holds, weak ones
     * add Nitsche's terms on both sides of interior faces too, in place of
     * the interior consistency terms of the held components, and leave
     * the body force on held components to the reactions.
     */
    bool dirichlet_inside = false;
  };

  /**
   * The smallest ratio of a Cholesky pivot L_jj^2 to the diagonal entry
   * K_jj it came from that counts as positive; below it the matrix is
   * taken as singular.
   */
  constexpr double singular_pivot_ratio = 1e-12;

  /// The outcome of a positive definiteness check of the stiffness matrix.
  enum class Definiteness
  {
    /// The Cholesky factorization succeeded with every pivot ratio above
    /// singular_pivot_ratio.
    positive_definite,
    /// The Cholesky factorization failed, or a pivot ratio fell below
    /// singular_pivot_ratio.
    not_positive_definite,
    /// The Cholesky factor would store more values than 'Definiteness
    /// check limit'.
    not_checked
  };

  /// "positive definite", "NOT positive definite" or "not checked".
  std::string
  to_string(const Definiteness d);

  /// Why a DG system can have no finite solution, for the messages of
  /// every solver that fails on one ("the matrix is singular (...), or
  /// ...").
  std::string
  unsolvable_system_causes();

  /**
   * The stiffness matrix, load vector and solution of linear (or
   * corotated) elasticity, or of the Poisson problem, on a mesh with a
   * discontinuous element FE_DGQ/FE_DGP (interior penalty or Babuska-
   * Zlamal flux, paper sections 4-5) or, for comparison, a continuous FE_Q
   * (then there are no face terms and Dirichlet conditions are strong).
   *
   * Assembly runs MeshWorker::mesh_loop over cells, boundary faces and
   * interior faces (FEInterfaceValues), so hanging faces need no special
   * case. The face penalty is eq. (7), eta_f = eta area(f) (1/vol(K-) +
   * 1/vol(K+)), multiplied by the stiffness of the face: 2 mu_f on the
   * jump and lambda_f on its normal component, with mu_f and lambda_f the
   * larger of the two sides' values (the average stress {sigma} in the
   * consistency term carries the stiffer side's stress, so the penalty must
   * dominate it; lambda only enters the consistency term through the
   * normal jump, so it penalizes only that, as in Hansbo and Larson 2002).
   * A boundary face with weakly imposed Dirichlet data is a face to a
   * mirror image of its cell: eta_f = 2 eta area(f) / vol(K).
   */
  template <int dim>
  class System
  {
  public:
    /**
     * Sets up @p n_components copies of the scalar element @p scalar_fe
     * on @p triangulation (both must outlive this object, as must
     * @p parameters and @p data). @p n_components is 1 (Poisson) or dim
     * (elasticity).
     */
    System(const Triangulation<dim> &triangulation,
           const FiniteElement<dim> &scalar_fe,
           const unsigned int        n_components,
           const Parameters         &parameters,
           const ProblemData<dim>   &data);

    /**
     * Assembles the stiffness matrix and load vector at penalty @p eta and
     * load factor @p t. If @p current is given (corotated formulation,
     * DG and vector fields only), every element and face contribution is
     * warped with the rotations of the elements fitted to @p current
     * (paper section 7) and the load vector contains the warping offsets,
     * so that the solution of the system is the next fixed-point iterate.
     * The exception is Babuska-Zlamal's interior-face penalty, which stays
     * unwarped to keep its sparsity (doc/dg.md, "Formulation").
     */
    void
    assemble(const double          eta,
             const double          t,
             const Vector<double> *current = nullptr);

    /**
     * Checks the assembled matrix for positive definiteness by a sparse
     * Cholesky factorization (CHOLMOD), if its factor holds at most
     * 'Definiteness check limit' values (factor_values). A pivot at
     * round-off level (singular_pivot_ratio) counts as a failure.
     */
    Definiteness
    check_definiteness();

    /**
     * Settles the penalty and assembles at load factor @p t: with
     * 'Penalty = automatic', starts at eta = 1 and doubles until the
     * matrix is positive definite (at most 30 times); with a fixed penalty,
     * checks it. Throws ExcMessage naming DG/Penalty if the fixed penalty
     * gives a matrix that is not positive definite, if the automatic
     * penalty cannot be checked, or if it is combined with the
     * Babuska-Zlamal flux (Parameters::check_penalty()). Continuous
     * elements need no penalty.
     * Returns the outcome of the last check.
     */
    Definiteness
    settle_penalty(const double t);

    /// Solves the assembled system into solution: with the factor of the
    /// definiteness check if solves_with_check_factor(), else with
    /// linear_solver if it is set, else with UMFPACK.
    void
    solve();

    /**
     * The whole solve at the settled penalty: linear, or corotated with
     * 'Load steps' steps of fixed-point iterations (lagged rotations,
     * relaxed by Aitken's factor). Throws ExcMessage if the corotated
     * iteration does not reach its tolerance, or if it ends a load step in
     * a state that turns a cell inside out (smallest_jacobian() not
     * positive), a fixed point of the lagged rotations that is no
     * deformation. Returns the number of linear solves.
     */
    unsigned int
    run();

    /**
     * The coefficients of @p function (with as many components as the
     * field) by an L2 projection on each cell: exact for functions in the
     * element's local polynomial space. Discontinuous elements only.
     */
    void
    project_locally(const Function<dim> &function, Vector<double> &v) const;

    /**
     * The rotation of every cell (by active cell index): the rotation
     * closest to the least-squares affine fit A of the deformed positions
     * x + @p u over the cell's quadrature points. That is the orthogonal
     * factor of the polar decomposition of A where det A > 0, and a proper
     * rotation (det +1, from the singular value decomposition) also where
     * the cell is inverted or flat (det A <= 0), where the polar factor
     * would be a reflection or not unique.
     */
    std::vector<Tensor<2, dim>>
    rotations(const Vector<double> &u) const;

    /**
     * The jump seminorm J of u - @p exact (of @p u if @p exact is null):
     * the square root of the sum over faces F of w_F ||[u - exact]||^2 on F,
     * with w_F the weight of the penalty terms without eta and the
     * material: |F| (1/|K| + 1/|K'|) on the face between cells K and K'
     * (2/h on a uniform grid), where [.] is the jump and that of a
     * continuous @p exact vanishes; and 2 |F| / |K| on a boundary face,
     * where [.] is the trace, counted only with @p exact (every boundary
     * face, Dirichlet or not). For a scalar field with mu = 1 and Dirichlet
     * data on the whole boundary, the error in the energy norm of the
     * interior penalty method is then (|u - exact|_H1^2 + eta J^2)^(1/2);
     * for elasticity the energy norm weighs the jumps with the material
     * (2 mu |[u]|^2 + lambda ([u].n)^2), and J bounds it up to the
     * material's factors. A continuous element has no
     * jumps: only its boundary traces count. @p exact has as many
     * components as the field.
     */
    double
    jump_norm(const Vector<double> &u,
              const Function<dim>  *exact = nullptr) const;

    /// Whether the element is continuous (FE_Q): no face terms.
    bool
    continuous() const
    {
      return is_continuous;
    }

    /// The penalty eta the matrix was last assembled with.
    double
    penalty() const
    {
      return eta_used;
    }

    /// Wall time (s) of the last assembly spent in the local integrals.
    double integration_time = 0;
    /// Wall time (s) of the last assembly spent in adding into K and F.
    double assembly_time = 0;
    /// Wall time (s) of the last solve (factorization and substitution;
    /// the substitution only with the check's factor, whose factorization
    /// settle_penalty() did).
    double solve_time = 0;

    /**
     * Solves K x = b (K the assembled matrix, b the load vector) into x,
     * throwing ExcMessage if it cannot, where solve() has no factor of the
     * definiteness check (solves_with_check_factor()) and, with
     * cholesky_first, K is not positive definite; if empty, solve()
     * factorizes K with UMFPACK there. The scene solver sets it to the
     * scene's 'Linear solver'.
     */
    std::function<void(const SparseMatrix<double> &K,
                       Vector<double>             &x,
                       const Vector<double>       &b)>
      linear_solver;
    /**
     * Whether settle_penalty() keeps the Cholesky factor of a passed check
     * for solve(), as long as the matrix is not assembled anew. The factor
     * is exact, so it saves the solve's own factorization or iterations;
     * off by default, so that solve() times a solve of its own (the cost
     * study) and the factor's memory is freed.
     */
    bool solve_with_check_factor = false;

    /// Whether solve() will use the factor of the definiteness check.
    bool
    solves_with_check_factor() const
    {
      return factor_of_matrix;
    }

    /**
     * Whether solve(), where it has no factor of the definiteness check,
     * first factorizes K with sparse Cholesky, and uses linear_solver (or
     * UMFPACK) only where K is not positive definite; solve() turns it off
     * then, so that the later solves (corotated iterations) do not try
     * again. The factorizations of one sparsity pattern share their
     * ordering. Off by default.
     */
    bool cholesky_first = false;
    /// The solves of solve() with a Cholesky factor, their own
    /// (cholesky_first) or the penalty check's, counted since the System
    /// was made.
    unsigned int cholesky_solves = 0;

    /// Appended to the message of a corotated iteration that does not
    /// converge: what the caller's solver setting may have to do with it.
    std::string stall_hint;
    /// Values the Cholesky factor of the last check_definiteness() stores.
    double factor_values = 0;
    /// Penalty doublings of the last settle_penalty() (0 if fixed).
    unsigned int penalty_doublings = 0;

    /// The vector-valued element.
    FESystem<dim> fe;
    /// The (affine) mapping of the cells.
    MappingQ1<dim> mapping;
    /// Degrees of freedom on the mesh.
    DoFHandler<dim> dof_handler;
    /// Strongly imposed Dirichlet values (and hanging nodes for FE_Q).
    AffineConstraints<double> constraints;
    /// Sparsity of the cell and face couplings.
    SparsityPattern sparsity;
    /// The stiffness matrix K.
    SparseMatrix<double> matrix;
    /// The load vector F.
    Vector<double> rhs;
    /// The solution u.
    Vector<double> solution;

  private:
    /// settle_penalty() but for the factor's fate: the search (or the
    /// check of a fixed penalty), factorizing into check_factor.
    Definiteness
    search_penalty(const double t);

    /// check_definiteness() with @p cholesky, which keeps its ordering
    /// between the checks of one sparsity pattern (the penalty doublings).
    Definiteness
    check_definiteness(solver::SparseCholesky &cholesky);

    /// The factor of the checks of settle_penalty(); kept after them while
    /// factor_of_matrix.
    solver::SparseCholesky check_factor;
    /// Whether check_factor is the factor of the assembled matrix.
    bool factor_of_matrix = false;

    /// Rebuilds the strong Dirichlet constraints at load factor @p t.
    void
    make_constraints(const double t);

    /**
     * The smallest det(I + grad @p u) over the vertices and quadrature
     * points of every cell, and where it is: of values equal up to
     * round-off, the first in cell order (FirstSmallest). Elasticity only
     * (as many components as dimensions).
     */
    std::pair<double, Point<dim>>
    smallest_jacobian(const Vector<double> &u) const;

    const Parameters       &parameters;
    const ProblemData<dim> &data;
    const unsigned int      n_components;
    const bool              is_continuous;
    /// Whether every face of the mesh is normal to a coordinate axis.
    bool axis_aligned = true;
    /// dof_handler.begin_active(l) for every level l: the reference of
    /// reinit_thread_independently() for the level's active cells.
    std::vector<typename DoFHandler<dim>::active_cell_iterator> level_reference;
    /// Cell and face quadrature rules (Gauss, k+1 points per direction).
    const QGauss<dim>     quadrature;
    const QGauss<dim - 1> face_quadrature;
    /// The coefficients of the identity map x (corotated offsets X^0).
    Vector<double> identity;
    double         eta_used = 0;
  };
} // namespace ddfem::dg

#endif
