#include <deal.II/lac/lapack_full_matrix.h>

#include <ddfem/base/parsing.h>
#include <ddfem/base/statistics.h>
#include <ddfem/coarsening/fitting.h>

#include <algorithm>
#include <cmath>

namespace ddfem::coarsening
{
  void
  FitSettings::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Fitting");
    prm.declare_entry("Regularization",
                      "0.01",
                      Patterns::Double(0, max_regularization),
                      "Weight lambda of the regularization toward the fine "
                      "parameters (paper eq. 4; the paper uses 0.01). The "
                      "energy residuals are relative, and mu and C are "
                      "measured in units of the block's largest fine mu, "
                      "lambda in units of its largest fine lambda, so the "
                      "weight is dimensionless.");
    prm.declare_entry(
      "Spring regularization",
      "same",
      Patterns::Anything(),
      "The weight of the springs' C in a level-1 entry's "
      "fit, toward their fine value 0: 'same' (Regularization, "
      "as the paper weighs every parameter alike) or a "
      "number from 0 to 1e6, with which Regularization weighs only mu "
      "and lambda. With 1e-6 the springs are nearly free: without void "
      "the median held-out error falls from 7.3 % to 5.1 %, "
      "and a laminate's springs reach its stiffness along the "
      "layers. A weight below 1e-6 (0 included) is refused where the "
      "samples do not determine every spring (embedded samples add up "
      "the springs of points that share a direction), as is such a "
      "Regularization or Child regularization where they do not "
      "determine mu and lambda. The child fits and level 2 keep their "
      "own weights. See doc/metamaterial_database.md, 'Free "
      "springs'.");
    prm.declare_entry("Child regularization",
                      "1e-4",
                      Patterns::Double(0, max_regularization),
                      "The weight of a second fit of every level-1 entry, "
                      "from the same samples: the model of the block that "
                      "the second level (Levels = 2) samples and clusters. "
                      "A smaller weight than Regularization lets the fits "
                      "of homogeneous blocks correct the trilinear "
                      "element's bending stiffness, which level 2 inherits "
                      "from its children; level 1 keeps Regularization, "
                      "which is stiffer in compression. See "
                      "doc/coarsening.md, 'Level-1 weight'.");
    prm.declare_entry("Stiffness floor",
                      format_number(default_stiffness_floor),
                      Patterns::Double(1e-12, 1),
                      "Lower bound of every quadrature point's fitted shear "
                      "modulus, as a fraction of the block's largest fine "
                      "shear modulus, but never above its smallest (which "
                      "it would be beyond a contrast of 1 / this). Keeps "
                      "points over void children "
                      "slightly stiff so a coarse element never has "
                      "zero-energy modes (so it must be above 0). Lambda "
                      "and C are bounded below by 0.");
    prm.declare_entry("Point floor",
                      "0",
                      Patterns::Double(0, 1),
                      "Lower bound of every quadrature point's fitted mu and "
                      "lambda, as a fraction of the point's own fine values "
                      "(0: only the stiffness floor). Keeps the points of "
                      "mixed blocks from trading their stiffness away to "
                      "their neighbours.");
    prm.declare_entry("Held-out every",
                      "5",
                      Patterns::Integer(0),
                      "Every n-th pattern (force or embedded, all its "
                      "magnitudes) is held out of the fit and used to "
                      "measure the fit's relative energy error. 0 holds none "
                      "out and measures the error on the fitted samples; 1 "
                      "would leave the fit no samples and is rejected, as is "
                      "a number above the patterns of either kind (force or "
                      "embedded: Database/Sampling/Patterns split by "
                      "Embedded fraction), which would hold none of that "
                      "kind out.");
    prm.declare_entry("Laminate springs",
                      "false",
                      Patterns::Bool(),
                      "Whether a block split in two layers of one voxel "
                      "(two materials, or one on void) gets springs along "
                      "its layers' axes and diagonals, instead of only the "
                      "lines its mirror symmetries keep. Turn it on for "
                      "parts of one-voxel layers along their length: a "
                      "cantilever of such layers comes out 3.6 and 0.69 "
                      "times naive's error instead of 18 and 21 times. It "
                      "is off by default because it raised the level-1 "
                      "errors of the bridge and the character's skeleton "
                      "by a quarter and two fifths. See doc/coarsening.md, "
                      "'Layers one voxel thick along a part'.");
    prm.leave_subsection();
  }



  void
  FitSettings::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Fitting");
    regularization                = prm.get_double("Regularization");
    child_regularization          = prm.get_double("Child regularization");
    const std::string spring_text = prm.get("Spring regularization");
    stiffness_floor               = prm.get_double("Stiffness floor");
    point_floor                   = prm.get_double("Point floor");
    held_out_every                = prm.get_integer("Held-out every");
    laminate_springs              = prm.get_bool("Laminate springs");
    prm.leave_subsection();
    static_assert(max_regularization == 1e6,
                  "The messages and documentation name the bound 1e6.");
    spring_regularization.reset();
    if (spring_text != "same")
      {
        spring_regularization =
          parse_number(spring_text,
                       "Database/Fitting/Spring regularization (expected "
                       "'same' or a number from 0 to 1e6)");
        AssertThrow(*spring_regularization >= 0 &&
                      *spring_regularization <= max_regularization,
                    ExcMessage("Database/Fitting/Spring regularization = " +
                               spring_text +
                               ": expected 'same' or a number from 0 to "
                               "1e6."));
      }
    AssertThrow(held_out_every != 1,
                ExcMessage("Database/Fitting/Held-out every must be 0 (none "
                           "held out) or at least 2: 1 would hold out every "
                           "sample and leave the fit none."));
  }



  Vector<double>
  nonnegative_least_squares(const FullMatrix<double> &H,
                            const Vector<double>     &g)
  {
    const unsigned int n = g.size();
    Vector<double>     x(n);
    std::vector<bool>  passive(n, false);
    const double       tolerance = 1e-13 * std::max(g.linfty_norm(), 1e-300);

    // Solves H_PP z_P = g_P on the passive set, z = 0 elsewhere.
    const auto solve_passive = [&]() {
      std::vector<unsigned int> P;
      for (unsigned int j = 0; j < n; ++j)
        if (passive[j])
          P.push_back(j);
      FullMatrix<double> H_PP(P.size(), P.size());
      Vector<double>     g_P(P.size()), z_P(P.size()), z(n);
      for (unsigned int a = 0; a < P.size(); ++a)
        {
          g_P(a) = g(P[a]);
          for (unsigned int b = 0; b < P.size(); ++b)
            H_PP(a, b) = H(P[a], P[b]);
        }
      H_PP.gauss_jordan();
      H_PP.vmult(z_P, g_P);
      for (unsigned int a = 0; a < P.size(); ++a)
        z(P[a]) = z_P(a);
      return z;
    };

    // Lawson and Hanson: free the variable of the largest gradient, solve
    // on the free (passive) set, and where that leaves the feasible set,
    // step to its boundary and bound the variable that reaches it first
    // (set to 0 exactly: the step's round-off would leave it at 1e-17,
    // and the next step would not move). Each pass frees one variable and
    // lowers the objective; the method ends after finitely many.
    const auto objective = [&](const Vector<double> &v) {
      Vector<double> Hv(n);
      H.vmult(Hv, v);
      return 0.5 * (v * Hv) - g * v;
    };
    const unsigned int max_passes = 3 * n + 10;
    bool               optimal    = false;
    double             f          = 0; // the objective at x = 0
    // A variable whose gradient passes the tolerance by round-off only (the
    // passive solves of an ill-conditioned problem) can be freed without
    // lowering the objective, and would be freed again and again. Such a
    // pass is undone, and the variable is not freed again until a pass
    // lowers the objective. These passes do not count toward the limit: at
    // most n follow each other. Since every counted pass lowers the
    // objective, no state repeats.
    std::vector<bool> stalled(n, false);
    for (unsigned int passes = 0; passes < max_passes && !optimal;)
      {
        // Gradient of the objective's negative: w = g - H x.
        Vector<double> w(n);
        H.vmult(w, x);
        w.sadd(-1., 1., g);
        unsigned int best   = n;
        double       best_w = tolerance;
        for (unsigned int j = 0; j < n; ++j)
          if (!passive[j] && !stalled[j] && w(j) > best_w)
            {
              best   = j;
              best_w = w(j);
            }
        optimal = (best == n);
        if (optimal)
          break;
        const Vector<double>    x_before       = x;
        const std::vector<bool> passive_before = passive;
        passive[best]                          = true;

        for (unsigned int inner = 0; inner < max_passes; ++inner)
          {
            const Vector<double> z        = solve_passive();
            double               alpha    = 1;
            unsigned int         blocking = n;
            for (unsigned int j = 0; j < n; ++j)
              if (passive[j] && z(j) <= 0 && x(j) / (x(j) - z(j)) < alpha)
                {
                  alpha    = x(j) / (x(j) - z(j));
                  blocking = j;
                }
            if (blocking == n)
              {
                // z >= 0 where free (z_j = 0 with x_j = 0 steps nowhere).
                for (unsigned int j = 0; j < n; ++j)
                  x(j) = std::max(z(j), 0.);
                break;
              }
            for (unsigned int j = 0; j < n; ++j)
              x(j) += alpha * (z(j) - x(j));
            x(blocking) = 0;
            for (unsigned int j = 0; j < n; ++j)
              if (passive[j] && x(j) <= 0)
                {
                  passive[j] = false;
                  x(j)       = 0;
                }
          }
        if (const double f_new = objective(x); f_new < f)
          {
            f = f_new;
            ++passes;
            std::fill(stalled.begin(), stalled.end(), false);
          }
        else
          {
            x             = x_before;
            passive       = passive_before;
            stalled[best] = true;
          }
      }
    AssertThrow(optimal,
                ExcFitRefused(
                  "The bounded least squares of a metamaterial fit "
                  "did not end in " +
                  std::to_string(max_passes) +
                  " passes (an ill-conditioned fit? Database/"
                  "Fitting/Regularization > 0 keeps it definite)."));
    return x;
  }



  namespace
  {
    /// What a fit whose samples do not determine its parameters should
    /// change, for its messages.
    constexpr char undetermined_advice[] =
      " Give the regularization weights (Database/Fitting/Regularization, "
      "Spring regularization and Child regularization) values of at least "
      "1e-6 (which leaves the parameters nearly free), or more Database/"
      "Sampling/Patterns, or sample mixed blocks with force patterns "
      "(Database/Sampling/Embedded fraction = 0).";
  } // namespace



  bool
  determines_unknowns(const FullMatrix<double> &A)
  {
    const unsigned int m = A.m();
    if (m == 0)
      return true;
    std::vector<double> d(m);
    for (unsigned int a = 0; a < m; ++a)
      {
        if (!(A(a, a) > 0))
          return false;
        d[a] = 1 / std::sqrt(A(a, a));
      }
    LAPACKFullMatrix<double> S(m, m);
    for (unsigned int a = 0; a < m; ++a)
      for (unsigned int b = 0; b < m; ++b)
        S(a, b) = d[a] * A(a, b) * d[b];
    S.compute_svd();
    // Singular values in decreasing order; the largest is at least 1 (the
    // unit diagonal's mean).
    return S.singular_value(m - 1) > 1e-12 * S.singular_value(0);
  }



  std::vector<double>
  relative_energy_errors(const CoarseElement       &element,
                         const Metamaterial        &m,
                         const std::vector<Sample> &samples)
  {
    std::vector<double> errors;
    for (const Sample &s : samples)
      {
        double e;
        if (element.energy(s.corners, m, e))
          errors.push_back(std::abs(e - s.energy) / s.energy);
      }
    return errors;
  }



  MetamaterialFit::MetamaterialFit(const CoarseElement       &element,
                                   const std::vector<Sample> &samples,
                                   const Metamaterial        &prior,
                                   const FitSettings         &settings,
                                   const PointTies           &ties)
    : element(element)
    , prior(prior)
    , scale({{0, 0, 0}})
  {
    const unsigned int n_points = element.n_points();
    const unsigned int n        = 3 * n_points;
    Assert(prior.points.size() == n_points, ExcInternalError());
    Assert(ties.point_class.empty() || (ties.point_class.size() == n_points &&
                                        ties.has_spring.size() == n_points),
           ExcInternalError());

    // The unknowns, each listing the parameters it sets.
    for (unsigned int c = 0; c < n_points; ++c)
      for (unsigned int t = 0; t < 3; ++t)
        {
          std::vector<unsigned int> members;
          for (unsigned int q = 0; q < n_points; ++q)
            if (ties.point_class.empty() ? q == c : ties.point_class[q] == c)
              if (t < 2 || ties.has_spring.empty() || ties.has_spring[q])
                members.push_back(3 * q + t);
          if (!members.empty())
            unknowns.push_back(members);
        }

    // Each parameter is measured in units of the block's largest fine
    // value of its kind (C in units of mu), so the regularization weighs a
    // relative change of every parameter alike.
    for (const auto &p : prior.points)
      {
        scale[0] = std::max(scale[0], p.mu);
        scale[1] = std::max(scale[1], p.lambda);
      }
    AssertThrow(scale[0] > 0,
                ExcMessage("A block to fit needs a solid child."));
    scale[2] = scale[0];
    if (scale[1] == 0)
      scale[1] = scale[0];
    // Lower bounds of (mu, lambda, C) per point.
    const double floor = prior.stiffness_floor(settings.stiffness_floor);
    for (const auto &p0 : prior.points)
      lower.push_back({{std::max(floor, settings.point_floor * p0.mu),
                        settings.point_floor * p0.lambda,
                        0.}});

    // Normal equations of the scaled unknowns x = (p - lower) / scale. A
    // sample whose corner motion inverts the coarse element (det F <= 0 at
    // a point, whatever the parameters) is one the element cannot take: it
    // is left out of the fit and of the errors alike, and counted; so is
    // one whose energy is not finite and positive (an infinite one would
    // make every right-hand side NaN, and the solver stop at the bounds).
    std::vector<Sample>                held_out, fitted;
    Vector<double>                     row(n);
    std::vector<std::array<double, 3>> terms;
    std::vector<Vector<double>>        rows;
    std::vector<double>                rhs;
    for (const Sample &s : samples)
      {
        if (!(std::isfinite(s.energy) && s.energy > 0 &&
              element.energy_terms(s.corners, prior, terms)))
          {
            ++n_rejected;
            continue;
          }
        min_strain = held_out.empty() && fitted.empty() ?
                       s.strain :
                       std::min(min_strain, s.strain);
        max_strain = std::max(max_strain, s.strain);
        if (settings.held_out_every > 0 &&
            s.pattern % settings.held_out_every == settings.held_out_every - 1)
          {
            held_out.push_back(s);
            continue;
          }
        fitted.push_back(s);
        double lower_energy = 0;
        for (unsigned int q = 0; q < n_points; ++q)
          for (unsigned int t = 0; t < 3; ++t)
            {
              lower_energy += lower[q][t] * terms[q][t];
              row(3 * q + t) = terms[q][t] * scale[t] / s.energy;
            }
        rows.push_back(row);
        rhs.push_back((s.energy - lower_energy) / s.energy);
      }
    n_fit = rows.size();
    AssertThrow(n_fit > 0,
                ExcFitRefused("A metamaterial fit has no sample to fit: of " +
                              std::to_string(samples.size()) + ", " +
                              std::to_string(n_rejected) +
                              " were rejected (energies that are not finite "
                              "and positive, or motions that invert the coarse "
                              "element) and " +
                              std::to_string(held_out.size()) +
                              " held out (Database/Fitting/Held-out every). "
                              "Give more Database/Sampling/Patterns."));
    // The rows in the unknowns: an unknown's column sums its parameters'.
    const unsigned int m = unknowns.size();
    H.reinit(m, m);
    g.reinit(m);
    Vector<double> reduced(m);
    for (unsigned int s = 0; s < rows.size(); ++s)
      {
        reduced = 0;
        for (unsigned int a = 0; a < m; ++a)
          for (const unsigned int i : unknowns[a])
            reduced(a) += rows[s](i);
        for (unsigned int a = 0; a < m; ++a)
          {
            g(a) += reduced(a) * rhs[s] / rows.size();
            for (unsigned int b = 0; b < m; ++b)
              H(a, b) += reduced(a) * reduced(b) / rows.size();
          }
      }

    n_held_out    = held_out.size();
    error_samples = std::move(held_out.empty() ? fitted : held_out);
  }



  Metamaterial
  MetamaterialFit::parameters(
    const double                regularization,
    const std::optional<double> spring_regularization) const
  {
    const double spring_weight = spring_regularization.value_or(regularization);
    // The regularization sums over an unknown's parameters, which share
    // their fine value and bounds.
    FullMatrix<double> A = H;
    Vector<double>     b = g;
    for (unsigned int a = 0; a < unknowns.size(); ++a)
      for (const unsigned int i : unknowns[a])
        {
          const unsigned int q = i / 3, t = i % 3;
          const auto        &p0      = prior.points[q];
          const double       fine[3] = {p0.mu, p0.lambda, p0.anisotropy};
          const double       weight  = t == 2 ? spring_weight : regularization;
          A(a, a) += weight;
          b(a) += weight * (fine[t] - lower[q][t]) / scale[t];
        }
    // With a weight of 0, or one so small that round-off decides, the
    // samples alone must determine the unknowns it leaves free. Fewer
    // samples than unknowns cannot, and neither can embedded samples,
    // which move the corners affinely: every point sees the same
    // deformation, so only the sums of the points' moduli (or of springs
    // along one direction) count. The solver would split them arbitrarily
    // (stiff children soft) and report a fit without error.
    constexpr double checked_below = 1e-6;
    AssertThrow(std::min(regularization, spring_weight) >= checked_below ||
                  determines_unknowns(A),
                ExcFitRefused(
                  "A metamaterial fit with the regularization weights " +
                  Utilities::to_string(regularization) + " (mu, lambda) and " +
                  Utilities::to_string(spring_weight) + " (springs) has " +
                  std::to_string(n_fit) +
                  " samples that fix only combinations of its " +
                  std::to_string(unknowns.size()) + " unknowns, not each one." +
                  undetermined_advice));

    const Vector<double> x = nonnegative_least_squares(A, b);
    AssertThrow(all_finite(x),
                ExcFitRefused("A metamaterial fit gave parameters that are not "
                              "finite: its samples do not determine them." +
                              std::string(undetermined_advice)));
    std::vector<double> p(3 * prior.points.size());
    for (unsigned int q = 0; q < prior.points.size(); ++q)
      for (unsigned int t = 0; t < 3; ++t)
        p[3 * q + t] = lower[q][t];
    for (unsigned int a = 0; a < unknowns.size(); ++a)
      for (const unsigned int i : unknowns[a])
        p[i] += scale[i % 3] * x(a);
    Metamaterial result = prior;
    for (unsigned int q = 0; q < prior.points.size(); ++q)
      {
        result.points[q].mu         = p[3 * q];
        result.points[q].lambda     = p[3 * q + 1];
        result.points[q].anisotropy = p[3 * q + 2];
      }
    return result;
  }



  FitResult
  MetamaterialFit::fit(const double                regularization,
                       const std::optional<double> spring_regularization) const
  {
    FitResult result;
    result.material   = parameters(regularization, spring_regularization);
    result.n_fit      = n_fit;
    result.n_held_out = n_held_out;
    result.n_rejected = n_rejected;
    result.min_strain = min_strain;
    result.max_strain = max_strain;
    std::vector<double> errors =
      relative_energy_errors(element, result.material, error_samples);
    if (!errors.empty())
      {
        std::sort(errors.begin(), errors.end());
        result.median_error = quantile(errors, 0.5);
        result.max_error    = errors.back();
      }
    return result;
  }



  FitResult
  fit_metamaterial(const CoarseElement       &element,
                   const std::vector<Sample> &samples,
                   const Metamaterial        &prior,
                   const FitSettings         &settings)
  {
    return MetamaterialFit(element, samples, prior, settings)
      .fit(settings.regularization);
  }
} // namespace ddfem::coarsening
