#ifndef ddfem_dg_parameters_h
#define ddfem_dg_parameters_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/fe/fe.h>

#include <memory>
#include <string>

namespace ddfem::dg
{
  using namespace dealii;

  /**
   * The choices of the discontinuous Galerkin discretization (prm
   * subsection "DG"; the polynomial degree k is
   * "Discretization/Polynomial degree"). Every enum has an explicit value
   * per allowed prm string. parse_parameters() checks only the penalty;
   * the combinations are checked where they are used: 'automatic' with
   * Babuska-Zlamal by check_penalty() (called by System::search_penalty(),
   * SceneSolver's constructor and the studies' parse_parameters()), strong
   * Dirichlet conditions with
   * FE_DGP by SceneSolver's constructor.
   */
  struct Parameters
  {
    /// The numerical flux on interior faces (paper eqs. 6 and 8).
    enum class Flux
    {
      /// Symmetric interior penalty: consistency, symmetry and penalty terms.
      interior_penalty,
      /// Babuska-Zlamal: the penalty term only (inconsistent, always stable).
      babuska_zlamal
    };

    /// The shape functions of each element.
    enum class Element
    {
      /// Lagrange tensor-product polynomials Q_k (nodal, (k+1)^dim each).
      dgq,
      /// Complete polynomials P_k (non-nodal, 4 or 10 per element in 3D).
      dgp
    };

    /// How Dirichlet conditions are imposed.
    enum class Dirichlet
    {
      /// Nitsche's method: the boundary face is a face to a ghost element.
      weak,
      /// Constrained degrees of freedom (FE_DGQ only: needs nodes).
      strong
    };

    /// Small-strain or stiffness-warped elasticity.
    enum class Formulation
    {
      /// Linear elasticity, one linear solve.
      linear,
      /// Corotated: per-element rotations, fixed-point iteration per step.
      corotated
    };

    /// Declares the subsection "DG".
    static void
    declare_parameters(ParameterHandler &prm);

    /**
     * Reads "DG" and "Discretization/Polynomial degree". Checks only that
     * a 'Penalty' other than 'automatic' is a finite decimal number in
     * (0, 2^30]; the other entries are checked by their Patterns when the
     * file is read, and no combination is checked here.
     */
    void
    parse_parameters(ParameterHandler &prm);

    /**
     * The scalar element of the choice, FE_DGQ(k) or FE_DGP(k), in @p dim
     * dimensions.
     */
    template <int dim>
    std::unique_ptr<FiniteElement<dim>>
    make_element() const;

    /// 'Flux' as written in the prm file.
    std::string
    flux_name() const;

    /// 'Element' as written in the prm file.
    std::string
    element_name() const;

    /**
     * Throws ExcMessage if 'Penalty = automatic' is combined with the flux
     * @p flux = Babuska-Zlamal. Its stiffness matrix is positive definite
     * for every eta > 0, so the automatic rule (double eta from 1 until K
     * is positive definite) would always stop at eta = 1, where BZ's
     * O(1/eta) error is large. @p setting names the setting that chose the
     * flux, for the message.
     */
    void
    check_penalty(const Flux flux, const std::string &setting) const;

    /// Whether 'Penalty = automatic'.
    bool
    automatic_penalty() const
    {
      return penalty == 0;
    }

    /// 'Flux'.
    Flux flux = Flux::interior_penalty;
    /// 'Element'.
    Element element = Element::dgq;
    /// The polynomial degree k (1 or 2).
    unsigned int degree = 1;
    /// The global penalty eta of eq. (7); 0 means automatic.
    double penalty = 0;
    /// 'Dirichlet'.
    Dirichlet dirichlet = Dirichlet::weak;
    /// 'Formulation'.
    Formulation formulation = Formulation::linear;
    /// 'Load steps' of the corotated formulation.
    unsigned int load_steps = 5;
    /// 'Corotation iterations': fixed-point iterations per load step.
    unsigned int corotation_iterations = 50;
    /// 'Corotation tolerance': relative change of the solution.
    double corotation_tolerance = 1e-8;
    /// 'Definiteness check limit': most values the Cholesky factor of
    /// the definiteness check may store.
    double definiteness_check_limit = 3e8;
  };
} // namespace ddfem::dg

#endif
