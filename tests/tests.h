#ifndef ddfem_tests_h
#define ddfem_tests_h

// Small helpers for ddfem's tests in deal.II's harness. Debian does not
// ship deal.II's own tests.h; this is the little we need. A test prints to
// standard output, which the harness compares with its .output file.

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/timer.h>

#include <ddfem/app/application.h>
#include <ddfem/coarsening/database.h>
#include <ddfem/scene/scene.h>
#include <ddfem/solver/discretization.h>
#include <ddfem/solver/linear_solver.h>
#include <ddfem/solver/static_solver.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace ddfem::testing
{
  using namespace dealii;

  /// The content of the file @p file ("" if there is none).
  inline std::string
  content_of(const std::string &file)
  {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

  /**
   * A scene, its discretization and a static solver, set up from the text
   * of a parameter file exactly as the ddfem program does. Solver logs go
   * to standard output only if @p verbose. At coarsening @p level 1 or 2
   * the discretization is the coarse mesh with its material records left
   * zero (no coarsener runs). The logs go to @p screen instead if given.
   */
  struct Problem
  {
    explicit Problem(const std::string &prm_text,
                     const bool         verbose = false,
                     const unsigned int level   = 0,
                     std::ostream      &screen  = std::cout)
      : log(screen, verbose)
      , timer(log, TimerOutput::never, TimerOutput::wall_times)
    {
      app::declare_parameters(prm);
      prm.parse_input_from_string(prm_text);
      scene.parse_parameters(prm);
      parameters.parse_parameters(prm);
      linear_solver.parse_parameters(prm);
      prm.enter_subsection("Discretization");
      const unsigned int degree = prm.get_integer("Polynomial degree");
      prm.leave_subsection();
      discretization =
        std::make_unique<solver::Discretization>(scene, degree, level);
      solver = std::make_unique<solver::StaticSolver>(*discretization,
                                                      scene.boundary_conditions,
                                                      parameters,
                                                      linear_solver,
                                                      timer,
                                                      log);
      solver->setup();
    }

    /// Runs the load steps; returns the solver statistics.
    solver::StaticSolver::Statistics
    solve()
    {
      return solver->solve([](unsigned int, double) {});
    }

    ParameterHandler                        prm;
    ConditionalOStream                      log;
    TimerOutput                             timer;
    scene::Scene                            scene;
    solver::StaticSolver::Parameters        parameters;
    solver::LinearSolver                    linear_solver;
    std::unique_ptr<solver::Discretization> discretization;
    std::unique_ptr<solver::StaticSolver>   solver;
  };

  /**
   * Parameter text of a cantilever: a @p grid ("nx, ny, nz") of voxels,
   * clamped on its y- face, with the traction @p traction ("tx; ty; tz",
   * Pa) on its y+ face. Append further subsections to change it.
   */
  inline std::string
  cantilever(const std::string &grid, const std::string &traction)
  {
    return "subsection Geometry\n  set Grid size = " + grid +
           "\nend\n"
           "subsection Boundary conditions\n"
           "  subsection Condition 1\n"
           "    set Type = fixed\n"
           "    set Region = y-\n"
           "  end\n"
           "  subsection Condition 2\n"
           "    set Type = traction\n"
           "    set Region = y+\n"
           "    set Value = " +
           traction + "\n  end\nend\n";
  }

  /**
   * Parameter text of the boundary conditions of a box in uniaxial stress:
   * its x-, y- and z- faces slide on their planes (Conditions 1 to 3), and
   * Condition 4 of type @p type ("displacement" or "traction") acts on its
   * z+ face with the value @p value.
   */
  inline std::string
  uniaxial_conditions(const std::string &type, const std::string &value)
  {
    std::string text = "subsection Boundary conditions\n";
    for (const char *face : {"x-", "y-", "z-"})
      text += "  subsection Condition " + std::to_string(face[0] - 'x' + 1) +
              "\n    set Type = sliding\n    set Region = " + face +
              "\n  end\n";
    return text + "  subsection Condition 4\n    set Type = " + type +
           "\n    set Region = z+\n    set Value = " + value + "\n  end\nend\n";
  }

  /**
   * Parameter text of a compare run ('Run type = compare') of scene
   * @p name: the cantilever() of @p grid voxels of @p voxel m, the traction
   * @p traction on its tip and a probe at @p probe ("x, y, z").
   */
  inline std::string
  compare_run(const std::string &name,
              const std::string &grid,
              const std::string &probe,
              const std::string &voxel    = "0.02",
              const std::string &traction = "0; 0; -2000")
  {
    return "set Run type = compare\nset Scene name = " + name + "\n" +
           cantilever(grid, traction) + "subsection Geometry\n" +
           "  set Voxel size = " + voxel + "\n  set Probe points = " + probe +
           "\nend\n";
  }

  /**
   * Parameter text of a palette and a layout of layers @p thickness m
   * thick, normal to @p axis, cycling through the palette's materials
   * @p ids (the palette of prm/default.prm unless @p palette is given).
   */
  inline std::string
  layers(
    const std::string &thickness,
    const std::string &axis    = "y",
    const std::string &palette = "E=1e5 nu=0.45; E=1e6 nu=0.45; E=1e7 nu=0.45",
    const std::string &ids     = "1, 2, 3")
  {
    return "subsection Materials\n  set Palette = " + palette +
           "\nend\n"
           "subsection Layout\n"
           "  set Type = layers\n"
           "  subsection Layers\n"
           "    set Axis = " +
           axis + "\n    set Materials = " + ids +
           "\n    set Thickness = " + thickness + "\n  end\nend\n";
  }

  /**
   * Parameter text of output into @p directory without screen timings
   * (whose numbers change from run to run) and without VTU files.
   */
  inline std::string
  quiet_output(const std::string &directory)
  {
    return "subsection Output\n"
           "  set Output directory = " +
           directory +
           "\n"
           "  set Screen timings = false\n"
           "  set Write VTU = none\n"
           "end\n";
  }

  /**
   * Parameter text of the metamaterial database @p file, filled lazily
   * (Scope = scene) with cheap sampling: 10 force patterns of 2
   * magnitudes and 10 stretch directions per block.
   */
  inline std::string
  cheap_lazy_database(const std::string &file)
  {
    return "subsection Database\n"
           "  set File = " +
           file +
           "\n"
           "  set Scope = scene\n"
           "  subsection Sampling\n"
           "    set Patterns = 10\n"
           "    set Magnitudes = 2\n"
           "    set Stretch directions = 10\n"
           "  end\n"
           "end\n";
  }

  /**
   * Runs ddfem on the parameter text @p prm_text, written to NAME.prm with
   * quiet_output(NAME) appended, and returns its exit status and the
   * comparison.json it wrote (null if none). The screen output is dropped.
   * For 'Run type = compare'.
   */
  inline std::pair<int, nlohmann::json>
  run_comparison(const std::string &prm_text, const std::string &name)
  {
    std::ofstream(name + ".prm") << prm_text << quiet_output(name);
    std::ostringstream screen;
    const int          status = app::run({name + ".prm"}, screen, screen);
    std::ifstream      file(name + "/comparison.json");
    return {status,
            file ? nlohmann::json::parse(file) : nlohmann::json(nullptr)};
  }

  /**
   * Runs ddfem on the parameter file @p prm with the settings @p settings
   * ("Subsection/Name=value", each passed as --set), its output in
   * @p directory (removed first), and returns its exit status and the
   * summary.json it wrote (null if none). The screen output goes to
   * @p screen.
   */
  inline std::pair<int, nlohmann::json>
  run_model(const std::string              &prm,
            const std::string              &directory,
            const std::vector<std::string> &settings,
            std::ostream                   &screen)
  {
    std::filesystem::remove_all(directory);
    std::vector<std::string> arguments = {
      prm, "--set", "Output/Output directory=" + directory};
    for (const std::string &setting : settings)
      arguments.insert(arguments.end(), {"--set", setting});
    const int     status = app::run(arguments, screen, screen);
    std::ifstream file(directory + "/summary.json");
    return {status,
            file ? nlohmann::json::parse(file) : nlohmann::json(nullptr)};
  }

  /// The summary.json of run_model() of @p prm with @p settings into
  /// @p directory; throws ExcMessage with the run's screen output if the run
  /// fails or writes no summary.
  inline nlohmann::json
  run_successfully(const std::string              &prm,
                   const std::string              &directory,
                   const std::vector<std::string> &settings)
  {
    std::ostringstream screen;
    const auto [status, summary] = run_model(prm, directory, settings, screen);
    AssertThrow(status == 0 && !summary.is_null(), ExcMessage(screen.str()));
    return summary;
  }

  /// The rotation by @p degrees about the unit vector @p axis (Rodrigues).
  inline Tensor<2, 3>
  rotation_about(const Tensor<1, 3> &axis, const double degrees)
  {
    const double a = degrees * numbers::PI / 180;
    Tensor<2, 3> K;
    K[0][1] = -axis[2];
    K[0][2] = axis[1];
    K[1][0] = axis[2];
    K[1][2] = -axis[0];
    K[2][0] = -axis[1];
    K[2][1] = axis[0];
    return unit_symmetric_tensor<3>() + std::sin(a) * K +
           (1 - std::cos(a)) * K * K;
  }

  /**
   * The Comparison subsection of a compare run of ddfem and naive at level
   * 1 against the fine model, without the fine direct solver.
   */
  inline std::string
  ddfem_and_naive_level_1()
  {
    return "subsection Comparison\n"
           "  set Methods = ddfem, naive\n"
           "  set Levels = 1\n"
           "  set Fine direct solver limit = 0\n"
           "end\n";
  }

  /**
   * The mean vertex errors of the level-@p level models of the
   * comparison.json @p json, by method; @p converged says whether every
   * model of the run converged.
   */
  inline std::map<std::string, double>
  level_errors(const nlohmann::json &json,
               const unsigned int    level,
               bool                 &converged)
  {
    std::map<std::string, double> error;
    converged = true;
    for (const auto &run : json.at("runs"))
      {
        converged &= run.at("converged").get<bool>();
        if (run.at("level") == level)
          error[run.at("method")] = run.at("mean_vertex_error");
      }
    return error;
  }

  /**
   * The largest of @p first and @p rest, or NaN if any of them is NaN.
   * Running maxima of errors use it: std::max drops a NaN that comes
   * second, and the test would still print "below".
   */
  template <typename... Rest>
  double
  worst(const double first, const Rest... rest)
  {
    double result = first;
    for (const double value : {first, double(rest)...})
      result = std::isnan(result) || std::isnan(value) ?
                 std::numeric_limits<double>::quiet_NaN() :
                 std::max(result, value);
    return result;
  }

  /**
   * The positive number @p bound as "m x 10^e" (m to @p digits significant
   * digits), or "10^e" where m = 1. The harness's numdiff splits it at '^'
   * and compares the exponent e as a number of its own: a bound like
   * 1e-14, printed as such, would pass as equal to any other below
   * numdiff's absolute tolerance of 1e-6.
   */
  inline std::string
  power_of_ten(const double bound, const int digits = 3)
  {
    AssertThrow(bound > 0, dealii::ExcMessage("A bound must be positive."));
    int          e     = static_cast<int>(std::floor(std::log10(bound) + 1e-9));
    const double scale = std::pow(10., digits - 1);
    double       m     = std::round(bound / std::pow(10., e) * scale) / scale;
    if (m >= 10)
      {
        m /= 10;
        ++e;
      }
    std::ostringstream text;
    if (m != 1)
      text << std::setprecision(digits) << m << " x ";
    text << "10^" << e;
    return text.str();
  }

  /**
   * Removes the database file @p file and the build journals of its two
   * levels, and their temporaries (coarsening::database_files()), that an
   * earlier run of the test (killed, or timed out) may have left: a build
   * would resume from them.
   */
  inline void
  remove_database(const std::string &file)
  {
    for (const std::string &name : coarsening::database_files(file))
      std::filesystem::remove(name);
  }

  /// Prints "name: below bound" if @p value < @p bound, else "FAILED" with
  /// the value and bound (also for a NaN value); the bound as
  /// power_of_ten() writes it. With @p digits > 0 the value is printed too,
  /// to that many significant digits ("name: 0.65, below 7.5 x 10^-1"), so
  /// that the output pins a measured value while the bound states the
  /// claim; a positive value below 1e-3 as power_of_ten() writes it
  /// ("2.8 x 10^-11"), which numdiff's absolute tolerance of 1e-6 would
  /// not hold to its digits otherwise.
  inline void
  check_below(const std::string &name,
              const double       value,
              const double       bound,
              const int          digits = 0)
  {
    std::cout << name << ": ";
    if (value < bound)
      {
        if (digits > 0 && value > 0 && value < 1e-3)
          std::cout << power_of_ten(value, digits) << ", ";
        else if (digits > 0)
          {
            const auto precision = std::cout.precision(digits);
            std::cout << value << ", ";
            std::cout.precision(precision);
          }
        std::cout << "below " << power_of_ten(bound) << std::endl;
      }
    else
      std::cout << "FAILED, " << value << " >= " << power_of_ten(bound)
                << std::endl;
  }

  /// The names of the files in @p directory, sorted.
  inline std::set<std::string>
  file_names(const std::string &directory)
  {
    std::set<std::string> names;
    for (const auto &entry : std::filesystem::directory_iterator(directory))
      names.insert(entry.path().filename().string());
    return names;
  }
} // namespace ddfem::testing

#endif
