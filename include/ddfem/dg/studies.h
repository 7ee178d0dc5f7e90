#ifndef ddfem_dg_studies_h
#define ddfem_dg_studies_h

#include <deal.II/base/function.h>
#include <deal.II/base/parameter_handler.h>

#include <ddfem/dg/parameters.h>

#include <algorithm>
#include <ostream>
#include <string>
#include <vector>

namespace ddfem::dg
{
  using namespace dealii;

  /**
   * A smooth manufactured solution on the unit square or cube with
   * @p n_components components (1: Poisson, dim: elasticity),
   * u_c(x) = prod_d sin(pi x_d + 0.5 + 0.3 c + 0.2 d), non-zero on the
   * boundary. Values, gradients and Hessians are exact.
   */
  template <int dim>
  class ManufacturedSolution : public Function<dim>
  {
  public:
    /// The solution with @p n_components components.
    explicit ManufacturedSolution(const unsigned int n_components);

    /// u_c(p).
    double
    value(const Point<dim> &p, const unsigned int c = 0) const override;

    /// grad u_c(p).
    Tensor<1, dim>
    gradient(const Point<dim> &p, const unsigned int c = 0) const override;

    /// The Hessian of u_c at p.
    SymmetricTensor<2, dim>
    hessian(const Point<dim> &p, const unsigned int c = 0) const override;
  };

  /**
   * The load f = -div sigma(u) of an exact solution @p u (with Hessians)
   * at @p p: -mu Laplace(u) for one component, and -(mu Laplace(u) + (mu +
   * lambda) grad div u) for linear elasticity with Lame parameters @p mu,
   * @p lambda. Component c of the result is the load on component c.
   */
  template <int dim>
  Tensor<1, dim>
  manufactured_load(const Function<dim> &u,
                    const Point<dim>    &p,
                    const double         mu,
                    const double         lambda);

  /**
   * One method of the studies: continuous FE_Q(k), or a DG flux with
   * the element of the "DG" subsection, both of degree k.
   */
  struct StudyMethod
  {
    /// "CG Q1", "BZ quad", ...
    std::string name;
    /// FE_Q instead of a DG element.
    bool continuous;
    /// The DG flux (unused if continuous).
    Parameters::Flux flux;
    /// The polynomial degree k.
    unsigned int degree;
  };

  /**
   * The methods named in @p list ("CG Q1", "CG Q2", "BZ lin", "BZ quad",
   * "IP lin", "IP quad", comma separated).
   */
  std::vector<StudyMethod>
  parse_methods(const std::string &list);

  /**
   * Convergence of CG and DG (paper figure 4): the manufactured solution
   * on 2^l x 2^l squares (Poisson) and 2^l x 2^l x 2^l cubes (linear
   * elasticity, mu = 1, lambda = 1.5, i.e. nu = 0.3) with Dirichlet data
   * on the whole boundary (weak for DG, strong for CG, whatever
   * DG/Dirichlet says; the linear formulation whatever DG/Formulation
   * says). For each method a
   * ConvergenceTable of the L2 error, the broken H1 seminorm error, the
   * jump seminorm error (System::jump_norm()) and an estimate of the
   * condition number of K (column "cond est": the Lanczos estimate of one
   * unpreconditioned CG solve, with the load vector as its only right-hand
   * side), with observed rates in h. A grid whose definiteness check
   * passed is solved with the check's Cholesky factor, the others with
   * UMFPACK. The DG penalty
   * is that of subsection "DG" ('automatic' only without BZ methods,
   * see Parameters::check_penalty()); 'automatic' is settled on the coarsest
   * grid and kept on the finer ones (eq. 7 scales it with the mesh).
   * Declared in the prm subsection "DG convergence".
   */
  class ConvergenceStudy
  {
  public:
    /// Declares "DG convergence".
    static void
    declare_parameters(ParameterHandler &prm);

    /// Reads "DG convergence" and "DG".
    void
    parse_parameters(ParameterHandler &prm);

    /**
     * Runs the study, prints the tables to @p out, writes them to
     * dg_convergence.txt, .csv and .dat in @p directory, and draws them
     * (plot(), with gnuplot: report::check_gnuplot() tells beforehand
     * whether it works). @p directory must exist and hold no earlier run's
     * results (the application's write_output() sees to both).
     */
    void
    run(const std::string &directory, std::ostream &out) const;

    /// The tables, the gnuplot script and both problems' figures that
    /// run() may write into its directory.
    static std::vector<std::string>
    result_files();

  private:
    /// The smallest and largest of some values (none: lo > hi).
    struct Extent
    {
      double lo = 1e300, hi = -1e300;

      /// Widens it to take @p value.
      void
      add(const double value)
      {
        lo = std::min(lo, value);
        hi = std::max(hi, value);
      }

      /// Widens it to take @p other.
      void
      add(const Extent &other)
      {
        lo = std::min(lo, other.lo);
        hi = std::max(hi, other.hi);
      }

      /// Whether it holds any value.
      bool
      empty() const
      {
        return lo > hi;
      }
    };

    /// One data block of dg_convergence.dat: a problem and a method.
    struct Block
    {
      /// "2D Poisson" or "3D elasticity".
      std::string problem;
      /// "CG Q1", "BZ quad", ...
      std::string method;
      /// The DoFs of its grids, and its finite condition number estimates.
      Extent dofs, condition;
    };

    /**
     * Writes dg_convergence.gnuplot and runs gnuplot on it: per problem a
     * PNG with the L2, H1 and jump errors of every method against the
     * number of DoFs, log-log, and a panel with the condition number estimates
     * of the methods that have a finite one (no panel if none has: gnuplot
     * stops on a plot without a finite point). An axis that would hold one
     * value (one grid) spans the decade around it. @p blocks
     * describes the data blocks of dg_convergence.dat in order.
     */
    static void
    plot(const std::string &directory, const std::vector<Block> &blocks);

    Parameters               dg;
    std::vector<StudyMethod> methods;
    std::vector<std::string> problems;
    unsigned int             min_2d, max_2d, min_3d, max_3d;
    unsigned int             condition_limit;
  };

  /**
   * The paper's Table 1: 3D linear elasticity (the manufactured solution
   * of ConvergenceStudy on the unit cube) with BZ and IP, linear and
   * quadratic, on an n^3 mesh, and trilinear CG on the mesh whose number
   * of DoFs is closest to that of the linear DG methods. Reports DoFs,
   * sparsity and the wall times of integration (local matrices), assembly
   * (adding into K) and solve (UMFPACK), on one thread, and the ratios
   * DG/CG measured in the same run, all DG methods with the fixed penalty
   * of subsection "DG" (weak Dirichlet data and the linear formulation, as
   * in ConvergenceStudy; BZ needs a fixed one, see
   * Parameters::check_penalty()). Declared in "DG cost".
   */
  class CostStudy
  {
  public:
    /// Declares "DG cost".
    static void
    declare_parameters(ParameterHandler &prm);

    /// Reads "DG cost" and "DG".
    void
    parse_parameters(ParameterHandler &prm);

    /**
     * Runs the comparison, prints the table to @p out (times only if
     * @p timings) and writes it with times to dg_cost.txt in @p directory,
     * which must exist (the application's write_output() makes it).
     */
    void
    run(const std::string &directory,
        const bool         timings,
        std::ostream      &out) const;

    /// The file run() writes into its directory: dg_cost.txt.
    static std::vector<std::string>
    result_files();

  private:
    Parameters   dg;
    unsigned int resolution;
  };
} // namespace ddfem::dg

#endif
