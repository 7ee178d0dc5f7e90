#include <deal.II/fe/fe_dgp.h>
#include <deal.II/fe/fe_dgq.h>

#include <ddfem/base/parsing.h>
#include <ddfem/dg/parameters.h>

#include <limits>

namespace ddfem::dg
{
  void
  Parameters::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("DG");
    prm.declare_entry(
      "Flux",
      "interior penalty",
      Patterns::Selection("interior penalty|babuska-zlamal"),
      "Numerical flux on faces (Method = dg). 'interior penalty': symmetric "
      "interior penalty (consistency, symmetry and penalty terms, paper eq. "
      "8): converges at order k+1 in L2, needs a large enough penalty. "
      "'babuska-zlamal': the penalty term only (eq. 6): cheaper, positive "
      "definite for any penalty, but inconsistent (does not converge to the "
      "exact solution).");
    prm.declare_entry(
      "Element",
      "FE_DGQ",
      Patterns::Selection("FE_DGQ|FE_DGP"),
      "Shape functions per element, of degree k = 'Discretization/Polynomial "
      "degree' (1 or 2). FE_DGQ: Lagrange Q_k, (k+1)^3 nodes per element. "
      "FE_DGP: complete polynomials P_k (4 linear or 10 quadratic functions "
      "per element, the paper's non-nodal basis).");
    prm.declare_entry(
      "Penalty",
      "automatic",
      Patterns::Anything(),
      "Global penalty eta of eq. (7), eta_f = eta area(f) (1/vol(K-) + "
      "1/vol(K+)) times the larger stiffness of the two sides (2 mu on the "
      "jump, lambda on its normal component). 'automatic': start at eta = 1 "
      "and double until the stiffness matrix is positive definite (checked "
      "by a sparse Cholesky factorization, see 'Definiteness check limit'). "
      "A number in (0, 2^30]: that eta; if the matrix is not positive definite "
      "the run stops with an error. eta is not scaled with the polynomial "
      "degree k: the smallest stable eta grows about like k^2, so a fixed "
      "eta that holds for k = 1 may be too small for k = 2, where "
      "'automatic' searches per degree. 'automatic' is for interior penalty "
      "only: with babuska-zlamal every eta > 0 is positive definite, so the "
      "rule would stop at eta = 1, a soft glue with a large O(1/eta) error; "
      "babuska-zlamal needs a fixed eta (the paper uses 10 to 100).");
    prm.declare_entry(
      "Dirichlet",
      "weak",
      Patterns::Selection("weak|strong"),
      "How fixed, sliding and displacement conditions are imposed. 'weak': "
      "Nitsche's method (paper section 5: the outside of a boundary face is "
      "a ghost element with the prescribed displacement, penalized as an "
      "interior face; inside a box region both sides of every interior face "
      "are held so). 'strong': the nodes of FE_DGQ in the region are "
      "constrained (not available for the non-nodal FE_DGP). Either way a "
      "box holds what it contains, as CG holds every node in it.");
    prm.declare_entry(
      "Formulation",
      "linear",
      Patterns::Selection("linear|corotated"),
      "'linear': small-strain elasticity, one linear solve. 'corotated': "
      "stiffness warping (paper section 7) with a rotation per element "
      "from the polar decomposition of its least-squares affine map; "
      "solved by a fixed-point iteration per load step, relaxed by "
      "Aitken's factor.");
    prm.declare_entry("Load steps",
                      "5",
                      Patterns::Integer(1, 1000),
                      "Equal load increments of the corotated formulation.");
    prm.declare_entry(
      "Corotation iterations",
      "50",
      Patterns::Integer(2, 10000),
      "Maximum fixed-point iterations (rotations from the last iterate, "
      "one linear solve each, the iterates relaxed by Aitken's factor) per "
      "load step of the corotated formulation; the run fails if they do "
      "not reach the tolerance. At least 2: a step's first solve moves the "
      "solution from the last step's, only a second can show it settled.");
    prm.declare_entry(
      "Corotation tolerance",
      "1e-8",
      Patterns::Double(1e-14, 1e-2),
      "From 1e-14 to 1e-2. The corotated iteration stops when a solve "
      "changes the solution by less than this, relative to its norm.");
    prm.declare_entry(
      "Definiteness check limit",
      "3e8",
      Patterns::Double(0, 1e9),
      "Positive definiteness of K is checked by a sparse Cholesky "
      "factorization (CHOLMOD, in floating point, with a fill-reducing "
      "ordering) if its factor stores at most this many values (8 bytes "
      "each; a run's peak memory is larger: 2.45 GB for a DG cube of 98304 "
      "DoFs, whose factor stores 2.1e8; the ordering tells the number "
      "before the factorization). Larger systems are not checked: "
      "'Penalty = automatic' then stops with a message, a fixed penalty is "
      "solved unchecked and reported as such. At most 1e9 (8 GB).");
    prm.leave_subsection();
  }



  void
  Parameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Discretization");
    degree = prm.get_integer("Polynomial degree");
    prm.leave_subsection();
    prm.enter_subsection("DG");
    flux    = prm.get("Flux") == "interior penalty" ? Flux::interior_penalty :
                                                      Flux::babuska_zlamal;
    element = prm.get("Element") == "FE_DGQ" ? Element::dgq : Element::dgp;
    const std::string penalty_text = prm.get("Penalty");
    if (penalty_text == "automatic")
      penalty = 0;
    else
      {
        // A word other than 'automatic' gets the message of the range too.
        try
          {
            penalty = parse_number(penalty_text, "DG/Penalty");
          }
        catch (const ExceptionBase &)
          {
            penalty = std::numeric_limits<double>::quiet_NaN();
          }
        // The automatic penalty's range; beyond it the penalty terms swamp
        // the elastic ones to round-off.
        AssertThrow(penalty > 0 && penalty <= 1073741824.,
                    ExcMessage("DG/Penalty = " + penalty_text +
                               ": expected 'automatic' or a number in (0, "
                               "2^30 = 1073741824]."));
      }
    dirichlet =
      prm.get("Dirichlet") == "weak" ? Dirichlet::weak : Dirichlet::strong;
    formulation = prm.get("Formulation") == "linear" ? Formulation::linear :
                                                       Formulation::corotated;
    load_steps  = prm.get_integer("Load steps");
    corotation_iterations    = prm.get_integer("Corotation iterations");
    corotation_tolerance     = prm.get_double("Corotation tolerance");
    definiteness_check_limit = prm.get_double("Definiteness check limit");
    prm.leave_subsection();
  }



  void
  Parameters::check_penalty(const Flux flux, const std::string &setting) const
  {
    AssertThrow(
      !(automatic_penalty() && flux == Flux::babuska_zlamal),
      ExcMessage(
        "DG/Penalty = automatic cannot be used with " + setting +
        ": with the Babuska-Zlamal flux every penalty eta > 0 gives a "
        "positive definite stiffness matrix, so the automatic rule would stop "
        "at eta = 1, where BZ's O(1/eta) error is large. Give a fixed "
        "DG/Penalty (the paper uses 10 to 100)."));
  }



  template <int dim>
  std::unique_ptr<FiniteElement<dim>>
  Parameters::make_element() const
  {
    if (element == Element::dgq)
      return std::make_unique<FE_DGQ<dim>>(degree);
    return std::make_unique<FE_DGP<dim>>(degree);
  }



  std::string
  Parameters::flux_name() const
  {
    return flux == Flux::interior_penalty ? "interior penalty" :
                                            "babuska-zlamal";
  }



  std::string
  Parameters::element_name() const
  {
    return element == Element::dgq ? "FE_DGQ" : "FE_DGP";
  }



  template std::unique_ptr<FiniteElement<2>>
  Parameters::make_element<2>() const;
  template std::unique_ptr<FiniteElement<3>>
  Parameters::make_element<3>() const;
} // namespace ddfem::dg
