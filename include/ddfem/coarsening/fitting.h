#ifndef ddfem_coarsening_fitting_h
#define ddfem_coarsening_fitting_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <ddfem/coarsening/block_sampler.h>
#include <ddfem/coarsening/metamaterial.h>

#include <optional>
#include <vector>

namespace ddfem::coarsening
{
  using namespace dealii;

  /**
   * The largest regularization weight a fit accepts (Database/Fitting/
   * Regularization, Spring regularization, Child regularization and
   * Database/Level 2/Regularization). At 1e6 a fit is already the fine
   * parameters, the naive element: the default scene's ddfem probe equals
   * naive's to five digits. Far larger weights overflowed the least-squares
   * solver (at 1e305 every fit collapsed).
   */
  constexpr double max_regularization = 1e6;

  /**
   * A metamaterial fit that its samples and settings cannot give (no
   * sample left, unknowns the samples leave free at a weight of 0,
   * parameters that are not finite, a bounded least squares that does not
   * end). The fit depends only on its combination's seed and the settings,
   * so the same settings fail it again.
   */
  DeclException1(ExcFitRefused, std::string, << arg1);

  /**
   * Settings of the metamaterial fit (paper eq. 4). Declared in the prm
   * subsection "Fitting".
   */
  struct FitSettings
  {
    /// Weight lambda of the regularization toward the fine parameters.
    double regularization = 0.01;
    /// The weight of the springs' C (toward their fine value, 0) in a
    /// level-1 entry's fit, if it is not regularization's ('same').
    std::optional<double> spring_regularization;
    /// The weight of each level-1 entry's second fit of the same samples:
    /// the model the second level samples as that block.
    double child_regularization = 1e-4;
    /// Lower bound of every point's shear modulus, as a fraction of the
    /// block's largest fine shear modulus.
    double stiffness_floor = default_stiffness_floor;
    /// Lower bound of every point's mu and lambda as a fraction of the
    /// point's own fine values.
    double point_floor = 0;
    /// Every n-th pattern (force or embedded) is held out of the fit to
    /// measure its error (0: none held out; the error is then measured on
    /// the fit's own samples).
    unsigned int held_out_every = 5;
    /// Whether blocks split in two layers get laminate springs
    /// (laminate_springs()) instead of the springs their symmetries keep.
    bool laminate_springs = false;

    /// Declares the subsection "Fitting".
    static void
    declare_parameters(ParameterHandler &prm);
    /// Reads the subsection "Fitting".
    void
    parse_parameters(ParameterHandler &prm);
  };

  /// A fitted metamaterial and how well it fits.
  struct FitResult
  {
    /// The fitted parameters and directions.
    Metamaterial material;
    /// Median relative energy error |E_fit - E_fine| / E_fine over the
    /// held-out samples (over the fitted ones if none is held out: n_held_out
    /// = 0).
    double median_error = 0;
    /// Largest relative energy error over the same samples.
    double max_error = 0;
    /// Samples used for the fit, held out (the errors' samples), and
    /// rejected from either because their energy is not finite and positive
    /// or the coarse element inverts (det F <= 0) under their corner motion.
    unsigned int n_fit = 0, n_held_out = 0, n_rejected = 0;
    /// Smallest and largest Sample::strain of the samples fitted or held
    /// out (0 if there are none); rejected samples do not count.
    double min_strain = 0, max_strain = 0;
  };

  /**
   * The fit of a metamaterial to energy samples (paper eq. 3-4): the
   * parameters (mu, lambda, C) of every point of @p element minimize
   *
   *   1/n sum_s ((E_s - E(p; u_s)) / E_s)^2
   *     + regularization * sum_j ((p_j - p0_j) / s_j)^2
   *
   * subject to mu >= max(min(stiffness_floor * s_mu, smallest solid mu0),
   * point_floor * mu0) (Metamaterial::stiffness_floor()),
   * lambda >= point_floor * lambda0 and C >= 0, with
   * p0 the parameters in @p prior (at level 1 the fine ones, C0 = 0; at
   * level 2 the children's fitted records), s_j the block's largest
   * fine value of p_j's kind (largest mu for mu and C, largest lambda for
   * lambda), and the directions taken from @p prior. The energy is linear
   * in p, so this is a bound-constrained linear least-squares problem,
   * solved exactly by an active-set method (nonnegative_least_squares()):
   * the bounds make non-physical parameters impossible. Residuals are
   * relative so soft and stiff samples weigh alike; the scaling measures
   * every change of a parameter relative to the block's largest fine value
   * of its kind, so in a mixed block a soft point's parameters are pulled
   * toward their fine values less than a stiff point's.
   *
   * With @p ties (symmetrize_directions()), the points of one class share
   * their unknowns and points without a spring have C = 0: the fit is then
   * the best symmetric one, not a symmetrized one.
   *
   * The constructor assembles the normal equations of the samples once;
   * parameters() and fit() solve them for any regularization weight.
   */
  class MetamaterialFit
  {
  public:
    /**
     * Assembles the problem (FitSettings::regularization is not used).
     * Throws ExcFitRefused if no sample can be fitted: every one is rejected
     * or held out.
     */
    MetamaterialFit(const CoarseElement       &element,
                    const std::vector<Sample> &samples,
                    const Metamaterial        &prior,
                    const FitSettings         &settings,
                    const PointTies           &ties = PointTies());

    /// The fitted metamaterial for the weight @p regularization of mu and
    /// lambda and @p spring_regularization of C (the same if not given).
    /// Where a weight is below 1e-6, the samples must determine every
    /// unknown (determines_unknowns()); throws ExcFitRefused if they do
    /// not, or if the parameters are not finite.
    Metamaterial
    parameters(const double                regularization,
               const std::optional<double> spring_regularization = {}) const;

    /// The fitted metamaterial for the weights of parameters(), with its
    /// errors on the held-out samples and the sample counts.
    FitResult
    fit(const double                regularization,
        const std::optional<double> spring_regularization = {}) const;

  private:
    const CoarseElement &element;
    Metamaterial         prior;
    /// Units of (mu, lambda, C) and every point's lower bounds of them.
    std::array<double, 3>              scale;
    std::vector<std::array<double, 3>> lower;
    /// The parameters 3 q + t (t: mu, lambda, C of point q) of every
    /// unknown: one per point and kind, or per tied class and kind. Springs
    /// that are not fitted have no unknown.
    std::vector<std::vector<unsigned int>> unknowns;
    /// Normal equations of the scaled unknowns x = (p - lower) / scale,
    /// without the regularization.
    FullMatrix<double> H;
    Vector<double>     g;
    /// The samples the fit's errors are measured on: the held-out ones,
    /// or the fitted ones if none is held out.
    std::vector<Sample> error_samples;
    unsigned int        n_fit = 0, n_held_out = 0, n_rejected = 0;
    /// The strain range of the samples fitted or held out.
    double min_strain = 0, max_strain = 0;
  };

  /// MetamaterialFit(element, samples, prior, settings).fit() with the
  /// weight FitSettings::regularization.
  FitResult
  fit_metamaterial(const CoarseElement       &element,
                   const std::vector<Sample> &samples,
                   const Metamaterial        &prior,
                   const FitSettings         &settings);

  /**
   * Minimizes 1/2 x^T H x - g^T x over x >= 0 for a symmetric positive
   * definite @p H (Lawson and Hanson's active-set method on the normal
   * equations). Exact up to round-off after finitely many steps. A pass
   * that frees a variable without lowering the objective (its gradient
   * above the tolerance by round-off only, as in ill-conditioned fits) is
   * undone, and that variable is not freed again until a pass lowers the
   * objective; it used to be freed and bounded until the passes ran out.
   * Throws ExcFitRefused if 3 n + 10 passes that lower the objective do
   * not reach the optimum.
   */
  Vector<double>
  nonnegative_least_squares(const FullMatrix<double> &H,
                            const Vector<double>     &g);

  /**
   * Whether the symmetric positive semidefinite matrix @p A of a fit's
   * normal equations (regularization included) determines every unknown
   * (true if there is none): false if a diagonal entry is not positive, or
   * if the smallest singular value of A scaled to a unit diagonal is at
   * most 1e-12 times its largest, where round-off cannot tell it from 0
   * (samples that fix only combinations of the unknowns).
   */
  bool
  determines_unknowns(const FullMatrix<double> &A);

  /**
   * Relative energy errors |E(m; u_s) - E_s| / E_s of metamaterial @p m on
   * @p samples (samples that invert the coarse element are skipped).
   */
  std::vector<double>
  relative_energy_errors(const CoarseElement       &element,
                         const Metamaterial        &m,
                         const std::vector<Sample> &samples);
} // namespace ddfem::coarsening

#endif
