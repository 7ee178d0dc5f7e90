#include <deal.II/base/convergence_table.h>
#include <deal.II/base/multithread_info.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/numerics/vector_tools.h>

#include <ddfem/base/exceptions.h>
#include <ddfem/base/files.h>
#include <ddfem/base/memory.h>
#include <ddfem/base/parsing.h>
#include <ddfem/dg/studies.h>
#include <ddfem/dg/system.h>
#include <ddfem/report/output.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <tuple>

namespace ddfem::dg
{
  namespace
  {
    /// Phase of factor d of component c of the manufactured solution.
    double
    phase(const unsigned int c, const unsigned int d)
    {
      return 0.5 + 0.3 * c + 0.2 * d;
    }

    /// Factor d of component c of the manufactured solution at @p p.
    template <int dim>
    double
    factor(const Point<dim> &p, const unsigned int c, const unsigned int d)
    {
      return std::sin(numbers::PI * p[d] + phase(c, d));
    }

    /// The derivative of factor() in direction d, divided by pi.
    template <int dim>
    double
    factor_derivative(const Point<dim>  &p,
                      const unsigned int c,
                      const unsigned int d)
    {
      return std::cos(numbers::PI * p[d] + phase(c, d));
    }

    /// The Lame parameters of the elasticity problems (nu = 0.3).
    constexpr double study_mu = 1, study_lambda = 1.5;
  } // namespace



  template <int dim>
  ManufacturedSolution<dim>::ManufacturedSolution(
    const unsigned int n_components)
    : Function<dim>(n_components)
  {}



  template <int dim>
  double
  ManufacturedSolution<dim>::value(const Point<dim>  &p,
                                   const unsigned int c) const
  {
    double u = 1;
    for (unsigned int d = 0; d < dim; ++d)
      u *= factor(p, c, d);
    return u;
  }



  template <int dim>
  Tensor<1, dim>
  ManufacturedSolution<dim>::gradient(const Point<dim>  &p,
                                      const unsigned int c) const
  {
    Tensor<1, dim> g;
    for (unsigned int i = 0; i < dim; ++i)
      {
        g[i] = numbers::PI;
        for (unsigned int d = 0; d < dim; ++d)
          g[i] *= d == i ? factor_derivative(p, c, d) : factor(p, c, d);
      }
    return g;
  }



  template <int dim>
  SymmetricTensor<2, dim>
  ManufacturedSolution<dim>::hessian(const Point<dim>  &p,
                                     const unsigned int c) const
  {
    SymmetricTensor<2, dim> H;
    for (unsigned int i = 0; i < dim; ++i)
      for (unsigned int j = i; j < dim; ++j)
        {
          H[i][j] = numbers::PI * numbers::PI * (i == j ? -1 : 1);
          for (unsigned int d = 0; d < dim; ++d)
            H[i][j] *= (d == i || d == j) && i != j ?
                         factor_derivative(p, c, d) :
                         factor(p, c, d);
        }
    return H;
  }



  template <int dim>
  Tensor<1, dim>
  manufactured_load(const Function<dim> &u,
                    const Point<dim>    &p,
                    const double         mu,
                    const double         lambda)
  {
    Tensor<1, dim> f;
    if (u.n_components == 1)
      {
        f[0] = -mu * trace(u.hessian(p, 0));
        return f;
      }
    for (unsigned int j = 0; j < dim; ++j)
      {
        const SymmetricTensor<2, dim> H = u.hessian(p, j);
        f[j] -= mu * trace(H);
        for (unsigned int i = 0; i < dim; ++i)
          f[i] -= (mu + lambda) * H[i][j];
      }
    return f;
  }



  std::vector<StudyMethod>
  parse_methods(const std::string &list)
  {
    std::vector<StudyMethod> methods;
    for (const std::string &name :
         split_list(list, ',', "DG convergence/Methods"))
      {
        const auto words = split_words(name);
        AssertThrow(words.size() == 2 &&
                      ((words[0] == "CG" &&
                        (words[1] == "Q1" || words[1] == "Q2")) ||
                       ((words[0] == "BZ" || words[0] == "IP") &&
                        (words[1] == "lin" || words[1] == "quad"))),
                    ExcMessage("Unknown study method \"" + name +
                               "\" in DG convergence/Methods: expected CG "
                               "Q1, CG Q2, BZ lin, BZ quad, IP lin or IP "
                               "quad."));
        StudyMethod m;
        m.name       = name;
        m.continuous = words[0] == "CG";
        m.flux       = words[0] == "BZ" ? Parameters::Flux::babuska_zlamal :
                                          Parameters::Flux::interior_penalty;
        m.degree     = (words[1] == "Q2" || words[1] == "quad") ? 2 : 1;
        methods.push_back(m);
      }
    return methods;
  }



  namespace
  {
    /// What one solve of the manufactured problem gave.
    struct Result
    {
      unsigned int cells    = 0;
      unsigned int dofs     = 0;
      std::size_t  nonzeros = 0;
      /// Errors: L2, broken H1 seminorm, and the jump seminorm
      /// (System::jump_norm(), boundary traces included).
      double l2 = 0, h1 = 0, jump = 0;
      double condition   = std::numeric_limits<double>::quiet_NaN();
      double eta         = 0;
      double integration = 0, assembly = 0, solve = 0;
      /// Whether the matrix is known to be positive definite: CG's is, a
      /// DG one was checked unless larger than DG/Definiteness check limit.
      /// A fixed penalty below the stable one gives an indefinite system
      /// whose errors mean nothing, so the studies say where it is not.
      bool checked = true;
    };

    /// The DG methods of the cost study (paper Table 1).
    constexpr const char *cost_methods = "BZ lin, IP lin, BZ quad, IP quad";

    /**
     * The scalar element of @p method: FE_Q, or the DG element of @p dg,
     * both of the method's degree.
     */
    template <int dim>
    std::unique_ptr<FiniteElement<dim>>
    study_element(const StudyMethod &method, const Parameters &dg)
    {
      if (method.continuous)
        return std::make_unique<FE_Q<dim>>(method.degree);
      Parameters parameters = dg;
      parameters.degree     = method.degree;
      return parameters.make_element<dim>();
    }

    /**
     * Throws ExcMessage naming @p setting (the parameter and its value)
     * if the system of @p method with @p n_components components on the
     * n^dim mesh of @p problem cannot fit into the machine's physical
     * memory: the entries of its sparsity pattern, 12 bytes each (value and
     * column). A Q_k element's pattern on the tensor grid is the tensor
     * product of n_components^2 one-dimensional ones of n (k+1)^2 - (n-1)
     * entries. A DG element's couples the pc functions (with their
     * components) of each cell with each other, pc^2 entries, and across
     * each of the dim n^(dim-1) (n-1) interior faces with the neighbor's:
     * all of them for IP (its flux has the gradients), 2 pc^2 entries; for
     * BZ only equal components of the m functions per component that are
     * not zero on the face (all of them for FE_DGP, (k+1)^(dim-1) for
     * FE_DGQ), 2 n_components m^2 (tests/dg/cost_sparsity*.prm count them).
     * A size that passes may still not fit, with UMFPACK's factor; one that
     * fails cannot.
     */
    template <int dim>
    void
    check_fits_in_memory(const unsigned int n,
                         const unsigned int n_components,
                         const StudyMethod &method,
                         const Parameters  &dg,
                         const std::string &problem,
                         const std::string &setting)
    {
      const double memory = physical_memory();
      double       entries;
      if (method.continuous)
        entries = std::pow(n_components, 2) *
                  std::pow(n * std::pow(method.degree + 1., 2) - (n - 1.), dim);
      else
        {
          const double pc =
            n_components * study_element<dim>(method, dg)->n_dofs_per_cell();
          const double m     = dg.element == Parameters::Element::dgp ?
                                 pc / n_components :
                                 std::pow(method.degree + 1., dim - 1);
          const double faces = dim * std::pow(double(n), dim - 1) * (n - 1.);
          entries            = std::pow(double(n), dim) * pc * pc +
                    faces * (method.flux == Parameters::Flux::interior_penalty ?
                               2 * pc * pc :
                               2 * n_components * m * m);
        }
      const double bytes = 12 * entries;
      AssertThrow(memory == 0 || bytes <= memory,
                  ExcMessage(setting + ": the " + std::to_string(n) + "^" +
                             std::to_string(dim) + " grid of " + problem +
                             " with " + method.name + " has a matrix of " +
                             format_number(bytes / (1u << 30)) +
                             " GiB, more than the physical memory of this "
                             "machine. Use a coarser grid."));
    }

    /**
     * Solves the manufactured problem on the n^dim mesh of the unit cube
     * with @p method (the DG choices of @p dg; its penalty must be fixed,
     * or automatic on a small enough system). Estimates the condition
     * number if there are at most @p condition_limit DoFs. If
     * @p solve_with_check_factor, a system whose definiteness check passed
     * is solved with the check's Cholesky factor, so that its matrix is
     * factorized once (System::solve_with_check_factor); otherwise
     * UMFPACK factorizes it again, a solve of its own that the cost study
     * times.
     */
    template <int dim>
    Result
    solve_manufactured(const unsigned int n,
                       const unsigned int n_components,
                       const StudyMethod &method,
                       const Parameters  &dg,
                       const unsigned int condition_limit,
                       const bool         solve_with_check_factor)
    {
      Triangulation<dim> tria;
      GridGenerator::subdivided_hyper_cube(tria, n, 0, 1);
      const ManufacturedSolution<dim> exact(n_components);
      const double                    mu = n_components == 1 ? 1 : study_mu;
      const double     lambda            = n_components == 1 ? 0 : study_lambda;
      ProblemData<dim> data;
      data.materials.assign(tria.n_active_cells(), {mu, lambda});
      data.body_force = [&](const Point<dim> &p) {
        return manufactured_load(exact, p, mu, lambda);
      };
      data.dirichlet = [&](const Point<dim>  &p,
                           const unsigned int c,
                           const double,
                           double &value) {
        value = exact.value(p, c);
        return true;
      };

      // The study is of linear elasticity (or Poisson) with weak
      // Dirichlet data for DG, whatever DG/Formulation and DG/Dirichlet say.
      Parameters parameters  = dg;
      parameters.flux        = method.flux;
      parameters.degree      = method.degree;
      parameters.dirichlet   = Parameters::Dirichlet::weak;
      parameters.formulation = Parameters::Formulation::linear;
      const std::unique_ptr<FiniteElement<dim>> scalar =
        study_element<dim>(method, parameters);
      System<dim> system(tria, *scalar, n_components, parameters, data);
      system.solve_with_check_factor  = solve_with_check_factor;
      const Definiteness definiteness = system.settle_penalty(1);
      system.solve();

      Result r;
      r.checked =
        method.continuous || definiteness != Definiteness::not_checked;
      r.cells          = tria.n_active_cells();
      r.dofs           = system.dof_handler.n_dofs();
      r.nonzeros       = system.matrix.n_nonzero_elements();
      r.eta            = system.penalty();
      r.integration    = system.integration_time;
      r.assembly       = system.assembly_time;
      r.solve          = system.solve_time;
      const auto error = [&](const VectorTools::NormType norm) {
        Vector<float> cellwise(tria.n_active_cells());
        VectorTools::integrate_difference(system.mapping,
                                          system.dof_handler,
                                          system.solution,
                                          exact,
                                          cellwise,
                                          QGauss<dim>(method.degree + 2),
                                          norm);
        return VectorTools::compute_global_error(tria, cellwise, norm);
      };
      r.l2   = error(VectorTools::L2_norm);
      r.h1   = error(VectorTools::H1_seminorm);
      r.jump = system.jump_norm(system.solution, &exact);

      if (r.dofs <= condition_limit)
        {
          SolverControl control(20 * r.dofs, 1e-12 * system.rhs.l2_norm());
          SolverCG<Vector<double>> cg(control);
          cg.connect_condition_number_slot(
            [&r](const double c) { r.condition = c; }, false);
          Vector<double> x(r.dofs);
          try
            {
              cg.solve(system.matrix, x, system.rhs, PreconditionIdentity());
            }
          catch (const SolverControl::NoConvergence &)
            {
              r.condition = std::numeric_limits<double>::infinity();
            }
        }
      return r;
    }

    /**
     * @p dg with its penalty fixed: an automatic penalty is settled on the
     * n^dim mesh (small) of the problem with @p method.
     */
    template <int dim>
    Parameters
    fixed_penalty(const Parameters  &dg,
                  const StudyMethod &method,
                  const unsigned int n,
                  const unsigned int n_components)
    {
      Parameters fixed = dg;
      if (dg.automatic_penalty() && !method.continuous)
        fixed.penalty =
          solve_manufactured<dim>(n, n_components, method, dg, 0, true).eta;
      return fixed;
    }

    /**
     * Compares the observed rates of the two finest grids of @p results
     * (refined by halving h) with theory: k+1 in L2 and k in the broken H1
     * seminorm for CG and the interior penalty flux, within 0.1, and at
     * least k - 0.1 in the jump seminorm (System::jump_norm()), which the
     * error in the energy norm bounds. The
     * Babuska-Zlamal flux is inconsistent at a fixed penalty: its L2 error
     * stalls at O(1/eta) once the grid is fine enough, which the line
     * reports as an L2 rate below 0.5. Returns one line ending in a newline.
     */
    std::string
    rate_verdict(const StudyMethod &method, const std::vector<Result> &results)
    {
      std::ostringstream line;
      if (results.size() < 2)
        {
          line << "One grid: no rate observed.\n";
          return line.str();
        }
      const Result &coarse = results[results.size() - 2];
      const Result &fine   = results.back();
      const double  l2     = std::log2(coarse.l2 / fine.l2);
      const double  h1     = std::log2(coarse.h1 / fine.h1);
      line << std::fixed << std::setprecision(2);
      if (!method.continuous && method.flux == Parameters::Flux::babuska_zlamal)
        line << "Inconsistent flux at a fixed penalty: L2 rate on the finest "
                "pair "
             << l2 << ", "
             << (l2 < 0.5 ? "stalled (below 0.5)" :
                            "not stalled on these grids")
             << "\n";
      else
        {
          const double k    = method.degree;
          const double jump = std::log2(coarse.jump / fine.jump);
          const bool   met  = std::abs(l2 - (k + 1)) <= 0.1 &&
                           std::abs(h1 - k) <= 0.1 &&
                           (fine.jump == 0 || jump >= k - 0.1);
          line << "Rates on the finest pair: L2 " << l2 << ", H1 " << h1
               << ", jump " << jump << "; theory " << method.degree + 1 << ", "
               << method.degree << " and at least " << method.degree
               << " (within 0.1): " << (met ? "reached" : "not reached")
               << "\n";
        }
      return line.str();
    }
  } // namespace



  void
  ConvergenceStudy::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("DG convergence");
    prm.declare_entry(
      "Problems",
      "2D Poisson, 3D elasticity",
      Patterns::MultipleSelection("2D Poisson|3D elasticity"),
      "Manufactured problems (Run type = dg convergence): -Laplace u = f on "
      "the unit square, and linear elasticity (mu = 1, lambda = 1.5) on the "
      "unit cube; the exact solution is smooth and non-zero on the "
      "boundary.");
    prm.declare_entry("Methods",
                      "CG Q1, CG Q2, IP lin, IP quad",
                      Patterns::MultipleSelection(
                        "CG Q1|CG Q2|BZ lin|BZ quad|IP lin|IP quad"),
                      "Methods to compare: continuous FE_Q(k), and DG with "
                      "the Babuska-Zlamal or interior penalty flux and the "
                      "element of subsection DG, k = 1 (lin) or 2 (quad). "
                      "BZ lin and BZ quad need a fixed DG/Penalty.");
    prm.declare_entry("2D refinements",
                      "2, 7",
                      Patterns::List(Patterns::Integer(0, 12), 2, 2),
                      "Smallest and largest l of the 2^l x 2^l grids; a "
                      "finest grid whose matrix alone could not fit into "
                      "the physical memory is refused.");
    prm.declare_entry("3D refinements",
                      "1, 3",
                      Patterns::List(Patterns::Integer(0, 7), 2, 2),
                      "Smallest and largest l of the 2^l x 2^l x 2^l grids; "
                      "a finest grid whose matrix alone could not fit into "
                      "the physical memory is refused.");
    prm.declare_entry(
      "Condition number limit",
      "20000",
      Patterns::Integer(0),
      "The condition number of K is estimated (column 'cond est': the "
      "Lanczos estimate of one unpreconditioned CG solve, with the load "
      "vector as right-hand side) for systems with at most this many DoFs; "
      "0 estimates none. It is printed as nan where it is not estimated "
      "(above the limit, or where CG converges in too few iterations for an "
      "estimate) and as inf where CG does not converge; the plot leaves out "
      "the methods without a finite estimate.");
    prm.leave_subsection();
  }



  void
  ConvergenceStudy::parse_parameters(ParameterHandler &prm)
  {
    dg.parse_parameters(prm);
    prm.enter_subsection("DG convergence");
    problems = split_list(prm.get("Problems"), ',', "DG convergence/Problems");
    methods  = parse_methods(prm.get("Methods"));
    AssertThrow(!problems.empty() && !methods.empty(),
                ExcMessage("DG convergence/Problems and Methods must each "
                           "name at least one entry."));
    // A study runs each entry once: a repeated one would only run again.
    for (const std::string parameter : {"Problems", "Methods"})
      check_each_once(prm.get(parameter), "DG convergence/" + parameter);
    for (const StudyMethod &method : methods)
      if (!method.continuous)
        dg.check_penalty(method.flux,
                         "the method " + method.name +
                           " of DG convergence/Methods");
    const auto l2d  = Utilities::string_to_int(split_list(
      prm.get("2D refinements"), ',', "DG convergence/2D refinements"));
    const auto l3d  = Utilities::string_to_int(split_list(
      prm.get("3D refinements"), ',', "DG convergence/3D refinements"));
    min_2d          = l2d[0];
    max_2d          = l2d[1];
    min_3d          = l3d[0];
    max_3d          = l3d[1];
    condition_limit = prm.get_integer("Condition number limit");
    prm.leave_subsection();
    // A refinements parameter with its value, as messages name it.
    const auto setting = [](const std::string &name,
                            const unsigned int smallest,
                            const unsigned int largest) {
      return "DG convergence/" + name + " = " + std::to_string(smallest) +
             ", " + std::to_string(largest);
    };
    const std::string setting_2d = setting("2D refinements", min_2d, max_2d);
    const std::string setting_3d = setting("3D refinements", min_3d, max_3d);
    for (const auto &[text, smallest, largest] :
         {std::tuple(setting_2d, min_2d, max_2d),
          std::tuple(setting_3d, min_3d, max_3d)})
      AssertThrow(smallest <= largest,
                  ExcMessage(text + ": expected 'smallest, largest' with "
                                    "smallest <= largest."));
    // Every problem and method on its finest grid.
    for (const std::string &problem : problems)
      for (const StudyMethod &method : methods)
        {
          const bool         poisson = problem == "2D Poisson";
          const std::string &setting = poisson ? setting_2d : setting_3d;
          poisson ? check_fits_in_memory<2>(
                      1u << max_2d, 1, method, dg, problem, setting) :
                    check_fits_in_memory<3>(
                      1u << max_3d, 3, method, dg, problem, setting);
        }
  }



  namespace
  {
    /// The figure of the convergence study's @p problem.
    std::string
    plot_file(std::string problem)
    {
      std::replace(problem.begin(), problem.end(), ' ', '_');
      return "dg_convergence_" + problem + ".png";
    }
  } // namespace



  std::vector<std::string>
  ConvergenceStudy::result_files()
  {
    return {"dg_convergence.txt",
            "dg_convergence.csv",
            "dg_convergence.dat",
            "dg_convergence.gnuplot",
            plot_file("2D Poisson"),
            plot_file("3D elasticity")};
  }



  void
  ConvergenceStudy::run(const std::string &directory, std::ostream &out) const
  {
    // The tables are written once the study is complete: a study that
    // fails (out of memory, say) leaves no partial files.
    std::ostringstream text, csv;
    csv << "problem,method,cells,dofs,L2,H1,jump,condition_estimate,eta\n";
    csv << std::setprecision(6);
    // The same numbers as gnuplot data blocks, one per problem and method.
    std::ostringstream dat;
    dat << std::setprecision(6);
    std::vector<Block> blocks;
    out << "DG convergence study, element " << dg.element_name()
        << ", Dirichlet weak (DG) / strong (CG)\n";
    for (const std::string &problem : problems)
      for (const StudyMethod &method : methods)
        {
          const bool          poisson = problem == "2D Poisson";
          const unsigned int  lo      = poisson ? min_2d : min_3d;
          const unsigned int  hi      = poisson ? max_2d : max_3d;
          const Parameters    fixed   = poisson ?
                                          fixed_penalty<2>(dg, method, 1u << lo, 1) :
                                          fixed_penalty<3>(dg, method, 1u << lo, 3);
          ConvergenceTable    table;
          std::vector<Result> results;
          dat << "# " << problem << ", " << method.name
              << "\n# cells dofs L2 H1 condition_estimate jump\n";
          blocks.push_back({problem, method.name, {}, {}});
          for (unsigned int l = lo; l <= hi; ++l)
            {
              Result r;
              try
                {
                  r = poisson ?
                        solve_manufactured<2>(
                          1u << l, 1, method, fixed, condition_limit, true) :
                        solve_manufactured<3>(
                          1u << l, 3, method, fixed, condition_limit, true);
                }
              catch (const ExceptionBase &e)
                {
                  // On a finer grid the penalty is the one settled on the
                  // coarsest, which a message would name as if fixed.
                  std::ostringstream context;
                  context << "On the " << (1u << l) << "^" << (poisson ? 2 : 3)
                          << " grid of " << problem << ", " << method.name
                          << ", with eta = " << fixed.penalty
                          << " (DG/Penalty = automatic, settled on the "
                          << (1u << lo) << "^" << (poisson ? 2 : 3)
                          << " grid): ";
                  AssertThrow(fixed.penalty == dg.penalty || l == lo,
                              ExcMessage(context.str() + message_of(e)));
                  throw;
                }
              results.push_back(r);
              table.add_value("cells", r.cells);
              table.add_value("dofs", r.dofs);
              table.add_value("L2", r.l2);
              table.add_value("H1", r.h1);
              table.add_value("jump", r.jump);
              table.add_value("cond est", r.condition);
              blocks.back().dofs.add(r.dofs);
              if (std::isfinite(r.condition))
                blocks.back().condition.add(r.condition);
              csv << problem << ',' << method.name << ',' << r.cells << ','
                  << r.dofs << ',' << r.l2 << ',' << r.h1 << ',' << r.jump
                  << ',' << r.condition << ',' << r.eta << '\n';
              dat << r.cells << ' ' << r.dofs << ' ' << r.l2 << ' ' << r.h1
                  << ' ' << r.condition << ' ' << r.jump << '\n';
            }
          dat << "\n\n";
          for (const std::string column : {"L2", "H1", "jump"})
            {
              table.set_scientific(column, true);
              table.set_precision(column, 3);
              table.evaluate_convergence_rates(
                column,
                "cells",
                ConvergenceTable::reduction_rate_log2,
                poisson ? 2 : 3);
            }
          table.set_scientific("cond est", true);
          table.set_precision("cond est", 2);
          std::ostringstream heading;
          heading << "\n" << problem << ", " << method.name;
          if (!method.continuous)
            heading << " (" << dg.element_name() << ", eta = " << fixed.penalty
                    << (dg.automatic_penalty() ? ", automatic" : "") << ")";
          std::vector<unsigned int> unchecked;
          for (const Result &r : results)
            if (!r.checked)
              unchecked.push_back(r.cells);
          if (!unchecked.empty())
            heading << ", positive definiteness NOT checked on "
                    << unchecked.size() << " grid(s) from " << unchecked[0]
                    << " cells on (DG/Definiteness check limit)";
          heading << ":\n";
          const std::string verdict = rate_verdict(method, results);
          out << heading.str();
          table.write_text(out);
          out << verdict;
          text << heading.str();
          table.write_text(text);
          text << verdict;
        }
    for (const auto &[name, content] :
         {std::make_pair("dg_convergence.txt", text.str()),
          std::make_pair("dg_convergence.csv", csv.str()),
          std::make_pair("dg_convergence.dat", dat.str())})
      {
        ResultFile file(directory + "/" + name, "Output/Output directory");
        file.stream() << content;
        file.commit();
      }
    plot(directory, blocks);
  }



  void
  ConvergenceStudy::plot(const std::string        &directory,
                         const std::vector<Block> &blocks)
  {
    // One figure per problem: errors (L2 solid, H1 dashed, jump dotted)
    // and condition number estimates against the number of DoFs, log-log,
    // as the paper's fig. 4 (DG has more DoFs than CG on a grid).
    ResultFile    file(directory + "/dg_convergence.gnuplot",
                    "Output/Output directory");
    std::ostream &script = file.stream();
    script << "set logscale xy\nset format y '10^{%L}'\nset key outside\n"
           << "set xlabel 'DoFs'\n";
    std::vector<std::string> problems, images;
    for (const Block &block : blocks)
      if (std::find(problems.begin(), problems.end(), block.problem) ==
          problems.end())
        problems.push_back(block.problem);
    // A log axis that holds one value (one grid; one condition estimate)
    // spans the decade around it, so that both ends are labelled: gnuplot
    // would warn of an empty range.
    const auto range = [](const Extent &values) {
      if (values.lo < values.hi)
        return std::string("[*:*]");
      int low  = std::floor(std::log10(values.lo)),
          high = std::ceil(std::log10(values.hi));
      if (low == high)
        --low, ++high;
      return "[1e" + std::to_string(low) + ":1e" + std::to_string(high) + "]";
    };
    for (const std::string &problem : problems)
      {
        images.push_back(plot_file(problem));
        Extent dofs, condition;
        for (const Block &b : blocks)
          if (b.problem == problem)
            {
              dofs.add(b.dofs);
              condition.add(b.condition);
            }
        script << "set xrange " << range(dofs) << "\n";
        // Panels: y label, the data columns drawn in it and its y range.
        struct Panel
        {
          std::string ylabel, columns, yrange;
        };
        std::vector<Panel> panels = {{"error", "346", "[*:*]"}};
        if (!condition.empty())
          panels.push_back(
            {"condition number estimate", "5", range(condition)});
        script << "set terminal pngcairo size " << 750 * panels.size()
               << ",500\nset output '" << images.back() << "'\n"
               << "set multiplot layout 1," << panels.size() << " title '"
               << problem << "'\n";
        for (const auto &[ylabel, columns, yrange] : panels)
          {
            script << "set ylabel '" << ylabel << "'\nset yrange " << yrange
                   << "\nplot ";
            // A method has the same marker and colour in every panel and
            // figure: its place in the study's list of methods.
            unsigned int series = 0;
            bool         first  = true;
            for (unsigned int b = 0; b < blocks.size(); ++b)
              if (blocks[b].problem == problem)
                {
                  for (const char column : columns)
                    if (column != '5' || !blocks[b].condition.empty())
                      {
                        script << (first ? "" : ", \\\n     ")
                               << "'dg_convergence.dat' index " << b
                               << " using 2:" << column << " with linespoints "
                               << report::gnuplot_style(series)
                               << (column == '4' ? " dashtype 2" :
                                   column == '6' ? " dashtype 3" :
                                                   "")
                               << " title '" << blocks[b].method
                               << (column == '3' ? " L2" :
                                   column == '4' ? " H1" :
                                   column == '6' ? " jump" :
                                                   "")
                               << "'";
                        first = false;
                      }
                  ++series;
                }
            script << "\n";
          }
        script << "unset multiplot\n";
      }
    file.commit();
    report::run_gnuplot(directory, "dg_convergence.gnuplot", images);
  }



  void
  CostStudy::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("DG cost");
    prm.declare_entry(
      "Resolution",
      "10",
      Patterns::Integer(1, 100),
      "Cells per direction n of the DG meshes (Run type = dg cost); the "
      "trilinear CG mesh is chosen with the number of DoFs closest to the "
      "linear DG methods (paper Table 1: 10 and 15 for FE_DGP). "
      "A resolution whose DG matrices alone could not fit into the physical "
      "memory is refused.");
    prm.leave_subsection();
  }



  void
  CostStudy::parse_parameters(ParameterHandler &prm)
  {
    dg.parse_parameters(prm);
    dg.check_penalty(Parameters::Flux::babuska_zlamal,
                     "Run type = dg cost, which compares BZ with IP");
    prm.enter_subsection("DG cost");
    resolution = prm.get_integer("Resolution");
    prm.leave_subsection();
    for (const StudyMethod &method : parse_methods(cost_methods))
      check_fits_in_memory<3>(resolution,
                              3,
                              method,
                              dg,
                              "3D linear elasticity",
                              "DG cost/Resolution = " +
                                std::to_string(resolution));
  }



  std::vector<std::string>
  CostStudy::result_files()
  {
    return {"dg_cost.txt"};
  }



  void
  CostStudy::run(const std::string &directory,
                 const bool         timings,
                 std::ostream      &out) const
  {
    // One thread, as the paper's timings and so that integration and
    // assembly times are separable; the caller's limit again afterwards,
    // also when a solve throws.
    struct RestoreThreads
    {
      ~RestoreThreads()
      {
        MultithreadInfo::set_thread_limit(n_threads);
      }
      const unsigned int n_threads = MultithreadInfo::n_threads();
    } restore_threads;
    MultithreadInfo::set_thread_limit(1);
    const std::vector<StudyMethod> dg_methods = parse_methods(cost_methods);
    // The solve times are UMFPACK's (factorization and substitution), not
    // those of a substitution with the definiteness check's factor.
    std::vector<std::pair<StudyMethod, Result>> results;
    for (const StudyMethod &method : dg_methods)
      results.emplace_back(
        method, solve_manufactured<3>(resolution, 3, method, dg, 0, false));
    // The CG mesh with the number of DoFs closest to linear DG.
    const double target = results[0].second.dofs;
    unsigned int n_cg   = 1;
    while (std::abs(3 * std::pow(n_cg + 2, 3) - target) <
           std::abs(3 * std::pow(n_cg + 1, 3) - target))
      ++n_cg;
    const StudyMethod cg   = parse_methods("CG Q1")[0];
    const Result reference = solve_manufactured<3>(n_cg, 3, cg, dg, 0, false);
    results.emplace_back(cg, reference);

    std::ostringstream table;
    table << "3D linear elasticity, DG element " << dg.element_name()
          << ", DG mesh " << resolution << "^3, CG mesh " << n_cg
          << "^3, one thread, UMFPACK\n"
          << std::left << std::setw(10) << "method" << std::right
          << std::setw(8) << "DoFs" << std::setw(10) << "nonzeros"
          << std::setw(9) << "spars.%" << std::setw(8) << "eta" << std::setw(10)
          << "L2 error";
    std::ostringstream times;
    times << std::setw(9) << "int. ms" << std::setw(9) << "ass. ms"
          << std::setw(10) << "solve ms" << std::setw(8) << "int/CG"
          << std::setw(8) << "ass/CG" << std::setw(9) << "solve/CG"
          << std::setw(9) << "total/CG";
    std::ostringstream screen, file;
    screen << table.str() << "\n";
    file << table.str() << times.str() << "\n";
    for (const auto &[method, r] : results)
      {
        std::ostringstream row, time_row;
        row << std::left << std::setw(10) << method.name << std::right
            << std::setw(8) << r.dofs << std::setw(10) << r.nonzeros
            << std::setw(9) << std::fixed << std::setprecision(3)
            << 100. * r.nonzeros / (double(r.dofs) * r.dofs) << std::setw(8)
            << std::setprecision(1) << r.eta << std::setw(10) << std::scientific
            << std::setprecision(2) << r.l2;
        const double total = r.integration + r.assembly + r.solve;
        const double total_cg =
          reference.integration + reference.assembly + reference.solve;
        time_row << std::fixed << std::setprecision(1) << std::setw(9)
                 << 1e3 * r.integration << std::setw(9) << 1e3 * r.assembly
                 << std::setw(10) << 1e3 * r.solve << std::setprecision(2)
                 << std::setw(8) << r.integration / reference.integration
                 << std::setw(8) << r.assembly / reference.assembly
                 << std::setw(9) << r.solve / reference.solve << std::setw(9)
                 << total / total_cg;
        screen << row.str() << "\n";
        file << row.str() << time_row.str() << "\n";
      }
    std::string unchecked;
    for (const auto &[method, r] : results)
      if (!r.checked)
        unchecked += (unchecked.empty() ? "" : ", ") + method.name;
    if (!unchecked.empty())
      {
        const std::string note = "positive definiteness NOT checked for " +
                                 unchecked + " (DG/Definiteness check limit)\n";
        screen << note;
        file << note;
      }
    out << (timings ? file.str() : screen.str());
    ResultFile text(directory + "/dg_cost.txt", "Output/Output directory");
    text.stream() << file.str();
    text.commit();
  }



  template class ManufacturedSolution<2>;
  template class ManufacturedSolution<3>;
  template Tensor<1, 2>
  manufactured_load(const Function<2> &,
                    const Point<2> &,
                    const double,
                    const double);
  template Tensor<1, 3>
  manufactured_load(const Function<3> &,
                    const Point<3> &,
                    const double,
                    const double);
} // namespace ddfem::dg
