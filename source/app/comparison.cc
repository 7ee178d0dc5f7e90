#include <deal.II/base/timer.h>

#include <ddfem/app/comparison.h>
#include <ddfem/app/model_run.h>
#include <ddfem/base/files.h>
#include <ddfem/base/parsing.h>
#include <ddfem/coarsening/coarsener.h>
#include <ddfem/dg/studies.h>
#include <ddfem/report/vertex_error.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

namespace ddfem::app
{
  namespace
  {
    /// One row of the comparison: a model's solve of one state.
    struct Row
    {
      std::string         state, method, grid, linear_solver;
      unsigned int        level = 0;
      std::size_t         cells = 0, dofs = 0;
      ModelRun::Result    result;
      report::VertexError error;
      /// Coarse rows: the error of the coarse grid's best fit to the fine
      /// solution and its lower bound (report::grid_fit()), the same for
      /// every method of a level.
      report::VertexError grid_fit;
      double              grid_bound = 0;
      /// Against the fastest converged fine run and the converged direct
      /// one; 0 where there is none or this run did not converge.
      double speedup = 0, speedup_direct = 0;

      /// Whether the row has vertex errors: a model that reached the full
      /// load, measured against a fine solution that reached it too.
      bool
      has_error() const
      {
        return error.n_vertices > 0;
      }

      /// Whether the row has a grid fit: a coarse model, with a fine
      /// solution at the full load to fit.
      bool
      has_grid_fit() const
      {
        return grid_fit.n_vertices > 0;
      }

      /// Whether the row is a reference of its state: a fine run that
      /// reached the full load, which the errors and speedups are measured
      /// against and the plot draws. A fine run that stopped before it is
      /// none: the table has its time, the plot does not.
      bool
      is_reference() const
      {
        return level == 0 && result.statistics.converged;
      }

      /// "fine", "fine-amg", "fine-direct" or "<method> L<level>".
      std::string
      label() const
      {
        return level == 0 ? method : method + " L" + std::to_string(level);
      }
    };

    /// The directory of the VTU files of model @p name at @p level:
    /// NAME, or NAME-L<level> for a coarse one, in @p directory.
    std::string
    model_directory(const std::string &directory,
                    const std::string &name,
                    const unsigned int level)
    {
      return directory + "/" + name +
             (level > 0 ? "-L" + std::to_string(level) : "");
    }

    /// The result files of a simulation and a comparison in the output
    /// directory: summary.json, the tables and the plot's files; and those
    /// of the DG studies, which a run there removes as an earlier run's.
    std::vector<std::string>
    result_files()
    {
      std::vector<std::string> files = {"summary.json",
                                        "comparison.json",
                                        "comparison.csv",
                                        "error_vs_time.dat",
                                        "error_vs_time.gnuplot",
                                        "error_vs_time.png"};
      for (const auto &study : {dg::ConvergenceStudy::result_files(),
                                dg::CostStudy::result_files()})
        files.insert(files.end(), study.begin(), study.end());
      return files;
    }

    /// The fine configurations of every comparison: name and linear solver
    /// ("" for the scene's).
    const std::vector<std::pair<std::string, std::string>> fine_runs =
      {{"fine", ""}, {"fine-amg", "cg-amg"}, {"fine-direct", "direct"}};

    /// The coarse methods a comparison can have.
    constexpr std::array<coarsening::CoarseningMethod, 3> coarse_methods = {
      {coarsening::CoarseningMethod::ddfem,
       coarsening::CoarseningMethod::naive,
       coarsening::CoarseningMethod::average}};

    /**
     * The marker of coarse model @p r in the plot (report::gnuplot_style()):
     * the same for a method and level in every plot, whichever others are
     * drawn.
     */
    unsigned int
    series_of(const Row &r)
    {
      const auto method = std::find(coarse_methods.begin(),
                                    coarse_methods.end(),
                                    coarsening::coarsening_method(r.method));
      return 2 * (method - coarse_methods.begin()) + r.level - 1;
    }

    /// The directory of every model a comparison can have in @p directory.
    std::vector<std::string>
    all_model_directories(const std::string &directory)
    {
      std::vector<std::string> result;
      for (const auto &[name, solver] : fine_runs)
        result.push_back(model_directory(directory, name, 0));
      for (const auto method : coarse_methods)
        for (const unsigned int level : {1u, 2u})
          result.push_back(
            model_directory(directory, coarsening::to_string(method), level));
      return result;
    }

    /**
     * Throws ExcMessage naming Database/File if @p database_file is the
     * directory @p d, which the run makes (@p what says which), or a
     * directory it lies in: the run would fit the database, then fail to
     * make the directory.
     */
    void
    require_database_outside(const std::string &database_file,
                             const std::string &d,
                             const std::string &what)
    {
      const std::filesystem::path file  = resolved_path(database_file);
      const std::filesystem::path place = resolved_path(d);
      AssertThrow(
        std::mismatch(file.begin(), file.end(), place.begin(), place.end())
            .first != file.end(),
        ExcMessage("Database/File = '" + database_file + "' is " + what +
                   ", or a directory it lies in. Name the database "
                   "otherwise, or keep it in another directory."));
    }

    /// "nx x ny x nz" of @p grid coarsened @p level times.
    std::string
    grid_text(const scene::VoxelGrid &grid, const unsigned int level)
    {
      const auto &n = grid.size();
      return std::to_string(n[0] >> level) + "x" +
             std::to_string(n[1] >> level) + "x" +
             std::to_string(n[2] >> level);
    }

    /// The paper-style table of @p rows (timings only if @p timings).
    void
    print_table(const std::vector<Row> &rows,
                const bool              timings,
                std::ostream           &out)
    {
      // The number format is set per column, and restored at the end.
      const std::ios_base::fmtflags flags     = out.flags();
      const std::streamsize         precision = out.precision();
      std::string                   state;
      for (const Row &row : rows)
        {
          if (row.state != state)
            {
              state = row.state;
              out << "\nState: " << state << "\n"
                  << std::left << std::setw(13) << "method" << std::setw(10)
                  << "grid" << std::right << std::setw(8) << "cells"
                  << std::setw(8) << "DoFs" << std::setw(8) << "Newton"
                  << std::setw(12) << "mean error" << std::setw(12)
                  << "max error" << std::setw(12) << "grid fit";
              if (timings)
                out << std::setw(10) << "wall [s]" << std::setw(12)
                    << "s/Newton" << std::setw(14) << "coarsen [ms]"
                    << std::setw(9) << "speedup" << std::setw(11)
                    << "sp.direct";
              out << "\n";
            }
          out << std::left << std::setw(13) << row.label() << std::setw(10)
              << row.grid << " " << std::right << std::setw(7) << row.cells
              << std::setw(8) << row.dofs << std::setw(8)
              << row.result.statistics.newton_iterations;
          out << std::scientific << std::setprecision(3);
          if (row.has_error())
            out << std::setw(12) << row.error.mean << std::setw(12)
                << row.error.max;
          else
            out << std::setw(12) << "-" << std::setw(12) << "-";
          out << std::setw(12);
          if (row.has_grid_fit())
            out << row.grid_fit.mean;
          else
            out << "-";
          out << std::defaultfloat;
          if (timings)
            {
              out << std::fixed << std::setprecision(3) << std::setw(10)
                  << row.result.wall_time << std::setw(12)
                  << row.result.time_per_iteration() << std::setw(14);
              if (row.result.coarse)
                out << 1e3 * row.result.coarsening_time;
              else
                out << "-";
              out << std::setprecision(1);
              for (const auto &[speedup, width] :
                   {std::pair(row.speedup, 9),
                    std::pair(row.speedup_direct, 11)})
                {
                  out << std::setw(width);
                  if (speedup > 0)
                    out << speedup;
                  else
                    out << "-";
                }
            }
          if (!row.result.statistics.converged)
            out << "  NOT CONVERGED";
          out << "\n";
        }
      out.flags(flags);
      out.precision(precision);
      out << std::flush;
    }

    /// Writes comparison.csv.
    void
    write_csv(const std::vector<Row> &rows, const std::string &file)
    {
      ResultFile    result(file, "Output/Output directory");
      std::ostream &csv = result.stream();
      csv << "state,method,level,grid,cells,dofs,newton_iterations,"
             "linear_iterations,direct_solves,preconditioner_setups,"
             "time_per_iteration_s,wall_time_s,coarsening_time_s,"
             "speedup_vs_fine,speedup_vs_fine_direct,mean_vertex_error,"
             "max_vertex_error,grid_fit_mean_vertex_error,"
             "grid_fit_max_vertex_error,grid_fit_lower_bound,"
             "linear_solver,converged\n"
          << std::setprecision(6);
      for (const Row &r : rows)
        {
          csv << r.state << ',' << r.method << ',' << r.level << ',' << r.grid
              << ',' << r.cells << ',' << r.dofs << ','
              << r.result.statistics.newton_iterations << ','
              << r.result.statistics.linear_iterations << ','
              << r.result.statistics.direct_solves << ','
              << r.result.statistics.preconditioner_setups << ','
              << r.result.time_per_iteration() << ',' << r.result.wall_time
              << ',';
          // Empty fields where a value does not exist: a fine run has no
          // coarsening, and a run without a converged fine reference no
          // grid fit.
          if (r.result.coarse)
            csv << r.result.coarsening_time;
          for (const double speedup : {r.speedup, r.speedup_direct})
            {
              csv << ',';
              if (speedup > 0)
                csv << speedup;
            }
          csv << ',';
          if (r.has_error())
            csv << r.error.mean << ',' << r.error.max;
          else
            csv << ',';
          csv << ',';
          if (r.has_grid_fit())
            csv << r.grid_fit.mean << ',' << r.grid_fit.max << ','
                << r.grid_bound;
          else
            csv << ",,";
          csv << ',' << r.linear_solver << ','
              << (r.result.statistics.converged ? "true" : "false") << '\n';
        }
      result.commit();
    }

    // gnuplot's list of labelled tics, "(label value, ...)", at 1, 2 and 5
    // times the powers of ten from @p low to @p high: errors and run times
    // often span little more than a decade, where powers of ten alone would
    // leave one label or two. (Over more than three decades, the powers of
    // ten alone.) Labels are "2e-3" where @p exponents, else "0.002".
    std::string
    log_tics(const double low, const double high, const bool exponents)
    {
      std::ostringstream tics;
      tics << "(";
      bool first = true;
      for (int e = static_cast<int>(std::floor(std::log10(low)));
           e <= static_cast<int>(std::ceil(std::log10(high)));
           ++e)
        for (const int m : {1, 2, 5})
          if (const double x = m * std::pow(10., e);
              x >= low && x <= high && (m == 1 || high <= 1e3 * low))
            {
              tics << (first ? "'" : ", '");
              first = false;
              if (exponents)
                tics << m << "e" << e;
              else
                tics << x;
              tics << "' " << x;
            }
      tics << ")";
      return tics.str();
    }



    /**
     * Draws error_vs_time.png: the mean vertex error of each coarse model
     * of the first state against its wall time, log-log, one marker per
     * method and level; the times of the fine runs that reached the full load
     * as vertical lines, and the error of each level's grid fit as a horizontal
     * one. If no coarse model of the first state has an error above 0,
     * says so on @p out instead.
     */
    void
    plot(const std::vector<Row> &rows,
         const std::string      &scene_name,
         const std::string      &directory,
         std::ostream           &out)
    {
      // One marker per coarse model of the first state; none, no plot.
      const auto is_marker = [&](const Row &r) {
        return r.state == rows.front().state && r.level > 0 && r.error.mean > 0;
      };
      if (std::none_of(rows.begin(), rows.end(), is_marker))
        {
          out << "No error_vs_time.png: no coarse model of state "
              << rows.front().state
              << " has a vertex error above 0 (none ran, reached the full "
                 "load, or had a fine solution at the full load to compare "
                 "with; or every error is 0, which a log axis cannot show)."
              << std::endl;
          return;
        }
      ResultFile    dat_file(directory + "/error_vs_time.dat",
                          "Output/Output directory");
      ResultFile    script_file(directory + "/error_vs_time.gnuplot",
                             "Output/Output directory");
      std::ostream &dat    = dat_file.stream();
      std::ostream &script = script_file.stream();
      script << "set terminal pngcairo size 900,650\n"
             << "set output 'error_vs_time.png'\n"
             << "set logscale xy\n"
             << "set xlabel 'wall time (s)'\n"
             << "set ylabel 'mean vertex error / longest side'\n"
             << "set key outside right\nset grid\n"
             // noenhanced: a scene name's _ or ^ is text, not a sub- or
             // superscript.
             << "set title "
             << report::gnuplot_string("Error against run time: " + scene_name)
             << " noenhanced\n";
      std::vector<std::string> curves;
      unsigned int             block  = 0;
      double                   lowest = 1e300, highest = 0;
      double                   fastest = 1e300, slowest = 0;
      // The fine runs drawn as lines: the first state's references.
      const auto is_fine_line = [&](const Row &r) {
        return r.state == rows.front().state && r.is_reference();
      };
      for (const Row &r : rows)
        if (is_marker(r) || is_fine_line(r))
          {
            fastest = std::min(fastest, r.result.wall_time);
            slowest = std::max(slowest, r.result.wall_time);
          }
      for (const Row &r : rows)
        if (is_marker(r))
          {
            dat << "# " << r.label() << "\n"
                << std::setprecision(6) << r.result.wall_time << " "
                << r.error.mean << "\n\n\n";
            lowest  = std::min(lowest, r.error.mean);
            highest = std::max(highest, r.error.mean);
            curves.push_back("'error_vs_time.dat' index " +
                             std::to_string(block) + " using 1:2 with points " +
                             "ps 2 " + report::gnuplot_style(series_of(r)) +
                             " title '" + r.label() + "'");
            ++block;
          }
      std::map<unsigned int, double> grid_fits;
      for (const Row &r : rows)
        if (r.state == rows.front().state && r.has_grid_fit() &&
            r.grid_fit.mean > 0) // a log axis has no 0
          grid_fits[r.level] = r.grid_fit.mean;
      // A fit at round-off (an affine solution) would stretch the axis
      // over many decades, and leave the markers in one corner.
      const double lowest_marker = lowest;
      for (const auto &[level, error] : grid_fits)
        if (error > 1e-3 * lowest_marker)
          {
            lowest  = std::min(lowest, error);
            highest = std::max(highest, error);
            script << "set arrow from graph 0, first " << error
                   << " to graph 1, first " << error << " nohead dashtype 3\n"
                   << "set label 'L" << level
                   << " grid fit' at graph 0.02, first " << error
                   << " offset 0,0.7\n";
          }
      // The fine runs' lines, labelled at staggered heights: their wall
      // times may differ by a few per cent only.
      unsigned int fine_lines = 0;
      for (const Row &r : rows)
        if (is_fine_line(r))
          script << "set arrow from " << r.result.wall_time << ", graph 0 to "
                 << r.result.wall_time << ", graph 1 nohead dashtype 2\n"
                 << "set label '" << r.label() << "' at " << r.result.wall_time
                 << ", graph " << 0.95 - 0.3 * (fine_lines++ % 3)
                 << " rotate by 90 right offset -1,0\n";
      dat_file.commit();
      const double y_min = lowest / 3, y_max = highest * 3;
      script << "set yrange [" << y_min << ":" << y_max << "]\nset ytics "
             << log_tics(y_min, y_max, true) << "\nset xrange [" << fastest / 2
             << ":" << slowest * 2 << "]\nset xtics "
             << log_tics(fastest / 2, slowest * 2, false) << "\nplot ";
      for (unsigned int c = 0; c < curves.size(); ++c)
        script << (c == 0 ? "" : ", \\\n     ") << curves[c];
      script << "\n";
      script_file.commit();
      report::run_gnuplot(directory,
                          "error_vs_time.gnuplot",
                          {"error_vs_time.png"});
    }
  } // namespace



  void
  Comparison::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Comparison");
    prm.declare_entry(
      "Methods",
      "ddfem, naive, average",
      Patterns::List(Patterns::Selection("ddfem|naive|average")),
      "Run type = compare: the coarse methods compared with the fine "
      "model (which always runs).");
    prm.declare_entry("Levels",
                      "1, 2",
                      Patterns::List(Patterns::Integer(1, 2)),
                      "Run type = compare: the coarsening levels each coarse "
                      "method runs at (1: 2x2x2 voxel blocks, 2: 4x4x4).");
    prm.declare_entry(
      "Fine direct solver limit",
      "200000",
      Patterns::Integer(0, std::numeric_limits<int>::max()),
      "Run type = compare: the fine model is solved with the scene's "
      "'Linear solver', with cg-amg if that is another solver, and, if it "
      "has at most this many unknowns, with UMFPACK at every Newton "
      "iteration (the solver class of the paper's timings).");
    prm.leave_subsection();
  }



  void
  Comparison::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Comparison");
    const std::string prm_methods = prm.get("Methods");
    const std::string prm_levels  = prm.get("Levels");
    const auto        method_names =
      split_list(prm_methods, ',', "Comparison/Methods");
    const auto level_list = Utilities::string_to_int(
      split_list(prm_levels, ',', "Comparison/Levels"));
    direct_limit = prm.get_integer("Fine direct solver limit");
    prm.leave_subsection();
    // No methods compares the fine solvers alone; methods need levels.
    AssertThrow(method_names.empty() || !level_list.empty(),
                ExcMessage("Comparison/Levels is empty: give the coarsening "
                           "levels (1, 2) of Comparison/Methods."));
    check_each_once(method_names, prm_methods, "Comparison/Methods");
    check_each_once(level_list, prm_levels, "Comparison/Levels");
    prm.enter_subsection("Discretization");
    degree = prm.get_integer("Polynomial degree");
    prm.leave_subsection();
    solver_parameters.parse_parameters(prm);
    vtu.parse_parameters(prm);
    database.parse_parameters(prm);

    const auto add = [&](const std::string &name,
                         const unsigned int level,
                         const std::string &linear_solver) {
      Configuration c;
      c.name          = name;
      c.level         = level;
      c.linear_solver = std::make_unique<solver::LinearSolver>();
      c.linear_solver->parse_parameters(prm);
      if (!linear_solver.empty())
        c.linear_solver->set_type(linear_solver);
      configurations.push_back(std::move(c));
    };
    configurations.clear();
    for (const auto &[name, solver] : fine_runs)
      add(name, 0, solver);
    for (const int level : level_list)
      for (const std::string &name : method_names)
        add(name, level, "");
  }



  void
  check_earlier_results(const std::string       &directory,
                        const report::VtuWriter &vtu,
                        const std::string       &database_file)
  {
    check_writable_in(directory, result_files(), "Output/Output directory");
    std::vector<std::string> directories = all_model_directories(directory);
    for (const std::string &d : directories)
      {
        vtu.check_writable(d, 0);
        // A comparison's model directory holds VTU files only: one with a
        // run's parameters.prm is that run's output directory, whose VTU
        // files this run would remove (or put its own next to).
        std::error_code error;
        AssertThrow(!std::filesystem::exists(d + "/parameters.prm", error),
                    ExcMessage("Output/Output directory = '" + directory +
                               "': '" + d +
                               "', where a compare run keeps a model's VTU "
                               "files (and any run into '" +
                               directory +
                               "' removes them as an earlier run's), holds "
                               "another run's results (its parameters.prm). "
                               "Use another output directory, or move that "
                               "run's results."));
      }
    // Nor may this run's directory be a model directory of a compare run,
    // whose VTU files it would remove or add to: as named (a link there
    // may lead elsewhere) and as resolved ('.', '..', links).
    std::vector<std::string> model_names;
    for (const std::string &d : all_model_directories("."))
      model_names.push_back(std::filesystem::path(d).filename().string());
    std::filesystem::path named =
      std::filesystem::path(directory).lexically_normal();
    if (!named.has_filename())
      named = named.parent_path();
    for (const std::filesystem::path &path : {named, resolved_path(directory)})
      {
        const std::filesystem::path parent =
          path.has_parent_path() ? path.parent_path() : ".";
        std::error_code error;
        AssertThrow(
          std::find(model_names.begin(),
                    model_names.end(),
                    path.filename().string()) == model_names.end() ||
            !std::filesystem::exists(parent / "comparison.json", error),
          ExcMessage("Output/Output directory = '" + directory +
                     "' is where the compare run in '" + parent.string() +
                     "' (its comparison.json) keeps a model's VTU "
                     "files: this run would remove them or add to "
                     "them. Use another output directory."));
      }
    if (database_file.empty())
      return;
    // The file and the directory it lies in, with their links followed.
    const std::filesystem::path file   = resolved_path(database_file);
    const std::string           name   = file.filename().string();
    const auto                  is_one = [&name](const std::string &result) {
      return name == result || name == ResultFile::partial_name(result);
    };
    // Runs write summary.json, parameters.prm and the comparison's tables
    // (or their temporaries) in the output directory, and VTU files there
    // and in every model's directory.
    const std::vector<std::string> files       = result_files();
    const bool                     result_here = is_one("parameters.prm") ||
                             std::any_of(files.begin(), files.end(), is_one);
    const bool vtu_name = report::VtuWriter::is_vtu_file(name);
    directories.push_back(directory);
    require_database_outside(database_file,
                             directory,
                             "Output/Output directory = '" + directory + "'");
    for (const std::string &d : directories)
      AssertThrow(!(vtu_name || (result_here && d == directory)) ||
                    resolved_path(d) != file.parent_path(),
                  ExcMessage("Database/File = '" + database_file +
                             "' is a result file of Output/Output directory "
                             "= '" +
                             directory +
                             "': this run would overwrite the database with "
                             "its results, or remove it as an earlier run's. "
                             "Name the database otherwise, or keep it in "
                             "another directory."));
  }



  void
  remove_earlier_results(const std::string &directory)
  {
    remove_earlier_in(directory, result_files(), "Output/Output directory");
    report::VtuWriter::remove_earlier(directory);
    for (const std::string &d : all_model_directories(directory))
      report::VtuWriter::remove_earlier(d);
  }



  void
  remove_failed_results(const std::string                        &directory,
                        const std::vector<std::filesystem::path> &made)
  {
    // Best effort: the error to report is the run's.
    try
      {
        remove_earlier_results(directory);
        remove_empty_directories(made);
      }
    catch (...)
      {}
  }



  int
  Comparison::run(const ParameterHandler         &prm,
                  scene::Scene                   &scene,
                  const std::string              &scene_name,
                  const std::string              &directory,
                  const std::vector<std::string> &inputs,
                  const bool                      screen_timings,
                  std::ostream                   &out)
  {
    out << "Comparison of scene \"" << scene_name << "\": grid "
        << scene.grid.describe() << ", " << scene.n_edits() << " material edit"
        << (scene.n_edits() == 1 ? "" : "s") << std::endl;
    // Every model solves the Neo-Hookean energy.
    scene.palette.require_nonnegative_lambda("Run type = compare");
    // The database settings matter to the ddfem models alone: checked up
    // to the highest ddfem level, which is prepared below.
    unsigned int ddfem_level = 0;
    for (const Configuration &c : configurations)
      if (c.name == "ddfem")
        ddfem_level = std::max(ddfem_level, c.level);
    if (ddfem_level > 0)
      database.check_simulation_input(scene.palette, ddfem_level);

    // The results are written once every model has run: gnuplot must start
    // and their files (each model's VTU files of every state too) must be
    // writable before any model is set up, the database is prepared and
    // anything runs.
    if (std::any_of(configurations.begin(),
                    configurations.end(),
                    [](const Configuration &c) { return c.level > 0; }))
      report::check_gnuplot("compare");
    check_earlier_results(directory,
                          vtu,
                          ddfem_level > 0 ? database.file() : "");
    vtu.check_writable(directory, 0);
    for (const Configuration &config : configurations)
      {
        const std::string d =
          model_directory(directory, config.name, config.level);
        if (vtu.enabled())
          {
            check_creatable(d, "Output/Output directory");
            if (ddfem_level > 0)
              require_database_outside(database.file(),
                                       d,
                                       "the directory '" + d +
                                         "' of a model's VTU files");
          }
        vtu.check_writable(d, scene.n_edits() + 1);
      }

    // The models, set up in order (the fine one first) before anything is
    // solved or written: invalid input (a grid that does not coarsen, a
    // probe outside a coarse model) stops the run with nothing written.
    // The ddfem models come last, after their database: the others check
    // the input before any fitting.
    std::optional<coarsening::Database>                 level1;
    coarsening::Hierarchy                               level2;
    ConditionalOStream                                  quiet(out, false);
    std::vector<std::unique_ptr<coarsening::Coarsener>> coarseners(
      configurations.size());
    std::vector<std::unique_ptr<ModelRun>> models(configurations.size());
    const auto                             set_up = [&](const unsigned int c) {
      const Configuration &config = configurations[c];
      if (config.level > 0)
        coarseners[c] = std::make_unique<coarsening::Coarsener>(
          coarsening::coarsening_method(config.name),
          config.level,
          scene.palette,
          database.point_offset(config.level),
          level1 ? &*level1 : nullptr,
          &level2);
      // The other fine solvers run only where they can be faster than the
      // fine model's own.
      std::string skip;
      if (config.name == "fine-amg" &&
          configurations[0].linear_solver->method() == "cg-amg")
        skip = "the fine model uses cg-amg already";
      if (config.name == "fine-direct" &&
          configurations[0].linear_solver->method() == "direct")
        skip = "the fine model uses direct already";
      else if (config.name == "fine-direct" &&
               models[0]->discretization().dof_handler.n_dofs() > direct_limit)
        skip = "more than " + std::to_string(direct_limit) +
               " unknowns (Comparison/Fine direct solver limit)";
      if (skip.empty())
        models[c] = std::make_unique<ModelRun>(scene,
                                               config.level == 0 ? degree : 1,
                                               coarseners[c].get(),
                                               solver_parameters,
                                               *config.linear_solver,
                                               quiet);
      else
        out << "  " << config.name << " skipped: " << skip << std::endl;
    };
    for (unsigned int c = 0; c < configurations.size(); ++c)
      if (configurations[c].name != "ddfem")
        set_up(c);

    // The database, completed lazily for this scene's blocks in every
    // state. A ddfem level without a baseline model on the same mesh is
    // checked with naive materials first.
    for (const Configuration &c : configurations)
      if (c.name == "ddfem")
        {
          bool checked = false;
          for (unsigned int b = 0; b < configurations.size(); ++b)
            checked =
              checked || (models[b] && configurations[b].level == c.level);
          if (!checked)
            // Coarse models are trilinear whatever the fine degree.
            check_coarse_model(scene,
                               1,
                               c.level,
                               database.point_offset(c.level),
                               solver_parameters,
                               *c.linear_solver);
        }
    if (ddfem_level > 0)
      {
        Timer preparation;
        level1.emplace(database.prepare(
          scene.palette, scene.states(), ddfem_level, level2, out));
        if (screen_timings)
          out << "  database preparation " << preparation.wall_time() << " s"
              << std::endl;
        for (unsigned int c = 0; c < configurations.size(); ++c)
          if (configurations[c].name == "ddfem")
            set_up(c);
      }

    // From here on results are written; none of an earlier run may stay
    // next to them, and a run that stops with an error before its tables
    // are written removes its own, and the directories it made (a plot
    // that fails leaves the tables and the VTU files it would draw from).
    // An earlier run's parameters.prm goes with its results, unless this
    // run reads it: a rerun from it keeps it should the rerun fail (this
    // run's own is written with its tables).
    made_directories = create_directories(directory, "Output/Output directory");
    remove_earlier_results(directory);
    if (!is_input_file(directory + "/parameters.prm", inputs))
      remove_earlier_in(directory,
                        {"parameters.prm"},
                        "Output/Output directory");
    bool tables_written = false;
    try
      {
        return solve_and_write(prm,
                               scene,
                               scene_name,
                               directory,
                               models,
                               screen_timings,
                               out,
                               tables_written);
      }
    catch (...)
      {
        if (!tables_written)
          remove_failed_results(directory, made_directories);
        throw;
      }
  }



  int
  Comparison::solve_and_write(const ParameterHandler &prm,
                              scene::Scene           &scene,
                              const std::string      &scene_name,
                              const std::string      &directory,
                              std::vector<std::unique_ptr<ModelRun>> &models,
                              const bool    screen_timings,
                              std::ostream &out,
                              bool         &tables_written)
  {
    const auto      &n = scene.grid.size();
    std::vector<Row> rows;
    bool             all_converged = true;
    for (unsigned int state = 0; state <= scene.n_edits(); ++state)
      {
        const std::string state_name =
          state == 0 ? "base" : "edit " + std::to_string(state);
        std::vector<std::size_t> changed;
        if (state > 0)
          {
            changed = scene.apply_edit(state - 1);
            out << "Edit " << state << ": " << changed.size()
                << " voxels change material" << std::endl;
          }
        const std::size_t                       first_row = rows.size();
        std::map<unsigned int, report::GridFit> grid_fits; // per level
        // The reference of the state's errors: its first fine model that
        // reached the full load (the fine models run first).
        const ModelRun *reference = nullptr;
        for (unsigned int c = 0; c < configurations.size(); ++c)
          {
            Configuration &config = configurations[c];
            if (!models[c])
              continue;
            ModelRun &model = *models[c];
            if (state > 0)
              model.edit(changed);

            Row row;
            row.state  = state_name;
            row.method = config.name;
            row.level  = config.level;
            row.grid   = grid_text(scene.grid, config.level);
            row.cells  = model.discretization().triangulation.n_active_cells();
            row.dofs   = model.discretization().dof_handler.n_dofs();
            const std::string run_directory =
              model_directory(directory, config.name, config.level);
            report::VtuWriter writer = vtu;
            writer.initialize(run_directory, state);
            if (writer.enabled())
              for (const auto &made :
                   create_directories(run_directory, "Output/Output directory"))
                made_directories.push_back(made);
            row.result        = model.solve(&writer);
            row.linear_solver = config.linear_solver->method();
            if (reference == nullptr && row.is_reference())
              reference = &model;
            if (reference != nullptr && row.result.statistics.converged)
              row.error = report::vertex_error(scene.grid,
                                               reference->discretization(),
                                               reference->solution(),
                                               model.discretization(),
                                               model.solution());
            if (config.level > 0 && reference != nullptr)
              {
                if (grid_fits.count(config.level) == 0)
                  {
                    Timer                  timer;
                    const report::GridFit &fit = grid_fits[config.level] =
                      report::grid_fit(scene.grid,
                                       reference->discretization(),
                                       reference->solution(),
                                       model.discretization());
                    if (screen_timings)
                      out << "  grid fit L" << config.level << ": "
                          << fit.iterations << " steps, " << timer.wall_time()
                          << " s" << std::endl;
                    if (!fit.converged)
                      out << "  Warning: the level " << config.level
                          << " grid fit stopped after " << fit.iterations
                          << " steps at a mean error of " << fit.error.mean
                          << ", above its lower bound " << fit.lower_bound
                          << std::endl;
                  }
                row.grid_fit   = grid_fits[config.level].error;
                row.grid_bound = grid_fits[config.level].lower_bound;
              }
            all_converged = all_converged && row.result.statistics.converged;
            out << "  " << std::left << std::setw(12) << row.label()
                << std::right << row.cells << " cells, " << row.dofs
                << " DoFs, " << row.linear_solver << ": "
                << (row.result.statistics.converged ? "converged " :
                                                      "NOT converged ")
                << row.result.statistics.describe()
                << ", max |u| = " << std::setprecision(4)
                << row.result.max_displacement << " m" << std::setprecision(6)
                << std::endl;
            rows.push_back(std::move(row));
          }

        // Speedups of the converged runs against the fastest converged fine
        // run and against the direct one: a fine run that failed early is
        // no reference.
        double fastest_fine = 0, direct_time = 0;
        for (std::size_t r = first_row; r < rows.size(); ++r)
          if (rows[r].is_reference())
            {
              const double time = rows[r].result.wall_time;
              if (fastest_fine == 0 || time < fastest_fine)
                fastest_fine = time;
              if (rows[r].linear_solver == "direct")
                direct_time = time;
            }
        for (std::size_t r = first_row; r < rows.size(); ++r)
          if (rows[r].result.statistics.converged)
            {
              rows[r].speedup        = fastest_fine / rows[r].result.wall_time;
              rows[r].speedup_direct = direct_time / rows[r].result.wall_time;
            }
      }

    print_table(rows, screen_timings, out);
    if (screen_timings)
      out << "speedup: against the fastest fine run that converged (fine: "
             "the scene's linear solver; fine-amg: CG with algebraic "
             "multigrid, where the fine model uses another solver; "
             "fine-direct); sp.direct: against the fine run with the direct "
             "solver (UMFPACK at every Newton iteration); mean and max error: "
             "against the first fine run of the state that converged; grid "
             "fit: the mean vertex error of the coarse grid's best trilinear "
             "fit to that solution. Wall times "
             "include setup and coarsening, not output."
          << std::endl;

    nlohmann::json json;
    json["scene"] = scene_name;
    json["grid"]  = {n[0], n[1], n[2]};
    json["runs"]  = nlohmann::json::array();
    for (const Row &r : rows)
      {
        nlohmann::json run   = r.result.to_json();
        run["state"]         = r.state;
        run["method"]        = r.method;
        run["level"]         = r.level;
        run["grid"]          = r.grid;
        run["cells"]         = r.cells;
        run["dofs"]          = r.dofs;
        run["linear_solver"] = r.linear_solver;
        // null where a value does not exist.
        const auto value = [](const double v, const bool exists) {
          return exists ? nlohmann::json(v) : nlohmann::json();
        };
        run["speedup_vs_fine"] = value(r.speedup, r.speedup > 0);
        run["speedup_vs_fine_direct"] =
          value(r.speedup_direct, r.speedup_direct > 0);
        run["mean_vertex_error"]          = value(r.error.mean, r.has_error());
        run["max_vertex_error"]           = value(r.error.max, r.has_error());
        const bool fit                    = r.has_grid_fit();
        run["grid_fit_mean_vertex_error"] = value(r.grid_fit.mean, fit);
        run["grid_fit_max_vertex_error"]  = value(r.grid_fit.max, fit);
        run["grid_fit_lower_bound"]       = value(r.grid_bound, fit);
        json["runs"].push_back(run);
      }
    const double peak_memory = peak_memory_mb();
    json["peak_memory_mb"]   = peak_memory;
    ResultFile file(directory + "/comparison.json", "Output/Output directory");
    file.stream() << json.dump(2) << std::endl;
    file.commit();
    write_csv(rows, directory + "/comparison.csv");
    // The parameters of these tables (not before: a rerun from the
    // directory's parameters.prm keeps it should this run fail).
    ResultFile used(directory + "/parameters.prm", "Output/Output directory");
    prm.print_parameters(used.stream(), ParameterHandler::ShortPRM);
    used.commit();
    tables_written = true;
    plot(rows, scene_name, directory, out);
    if (screen_timings)
      out << "Peak memory " << peak_memory << " MiB" << std::endl;
    return all_converged ? 0 : 1;
  }
} // namespace ddfem::app
