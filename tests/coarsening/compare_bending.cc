// Run type = compare on a small version of the bending scene: fine (with
// multigrid CG and with the direct solver), ddfem, naive and average at
// coarsening levels 1 and 2, the metamaterials fitted lazily into a fresh
// database. The screen table (without timings) is compared; the files the
// run writes are checked for their columns, their speedups against the
// fine runs' wall times, the CSV against the JSON, and the ddfem L1 run's
// probes against a simulation of that model. A second, smaller run
// compares a quadratic fine model with the trilinear naive one; a third one
// has a fine model that fails, and its errors are measured against the
// direct run, as a fourth run whose scene solves directly confirms. A
// fifth run's plot fails: its tables stay.

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "../tests.h"

namespace
{
  /// Output into @p directory without timings, VTU as @p vtu.
  std::string
  output(const std::string &directory, const std::string &vtu)
  {
    return "subsection Output\n  set Output directory = " + directory +
           "\n  set Screen timings = false\n  set Write VTU = " + vtu +
           "\nend\n";
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  ddfem::testing::remove_database("compare.h5");
  std::filesystem::remove_all("compare");

  // prm/bending.prm with half the voxels per direction, and layers of three
  // voxels: they cut through the 2x2x2 blocks, so that ddfem, naive and
  // average differ at level 1.
  std::ofstream prm("compare_bending.prm");
  prm << ddfem::testing::compare_run("bending", "4, 16, 4", "0.04, 0.32, 0.04")
      << ddfem::testing::layers("0.06")
      << "subsection Database\n"
         "  set File = compare.h5\n"
         "  subsection Sampling\n"
         "    set Patterns = 60\n"
         "    set Stretch directions = 60\n"
         "  end\n"
         "end\n"
      << output("compare", "last step");
  prm.close();

  const int status =
    ddfem::app::run({"compare_bending.prm"}, std::cout, std::cout);
  std::cout << "exit status " << status << std::endl;

  std::ifstream csv("compare/comparison.csv");
  std::string   header;
  std::getline(csv, header);
  std::cout << "comparison.csv header: " << header << std::endl;
  const auto split = [](const std::string &line) {
    std::stringstream        fields(line);
    std::vector<std::string> result;
    for (std::string field; std::getline(fields, field, ',');)
      result.push_back(field);
    return result;
  };
  const std::vector<std::string>        names = split(header);
  std::vector<std::vector<std::string>> csv_rows;
  for (std::string line; std::getline(csv, line);)
    csv_rows.push_back(split(line));
  std::cout << "comparison.csv rows: " << csv_rows.size() << std::endl;
  // A fine run has no coarsening and no grid fit: empty fields, not zeros.
  for (const unsigned int r : {0u, 3u})
    {
      std::cout << "  empty fields of the " << csv_rows[r][1] << " row:";
      for (unsigned int c = 0; c < names.size(); ++c)
        if (csv_rows[r][c].empty())
          std::cout << ' ' << names[c];
      std::cout << std::endl;
    }

  // comparison.json has every column of the CSV in every run.
  std::ifstream         json_file("compare/comparison.json");
  const nlohmann::json  json = nlohmann::json::parse(json_file);
  std::set<std::string> missing;
  for (const std::string &column : names)
    for (const auto &run : json.at("runs"))
      if (!run.contains(column))
        missing.insert(column);
  std::cout << "comparison.json runs: " << json.at("runs").size()
            << ", CSV columns missing in them:";
  for (const std::string &column : missing)
    std::cout << ' ' << column;
  std::cout << (missing.empty() ? " none" : "") << std::endl;
  // The fine runs of a state solve one model to the Newton tolerance with
  // other linear solvers: their errors against the first (printed in the
  // table, but below what numdiff compares) are at round-off.
  double fine_difference = 0;
  for (const auto &run : json.at("runs"))
    if (run.at("level") == 0)
      fine_difference =
        ddfem::testing::worst(fine_difference,
                              run.at("max_vertex_error").get<double>());
  ddfem::testing::check_below("max vertex error of the fine runs",
                              fine_difference,
                              1e-8);
  // Probes as in summary.json: the point and the displacement there,
  // equal to those of a simulation of the same model.
  const auto &ddfem_run = json.at("runs")[3];
  std::cout << "probes of the " << ddfem_run.at("method").get<std::string>()
            << " L" << ddfem_run.at("level") << " run:";
  for (const auto &probe : ddfem_run.at("probes"))
    std::cout << " point " << probe.at("point").dump();
  std::cout << std::endl;
  std::ostringstream simulation_screen;
  const auto [simulation_status, simulation] =
    ddfem::testing::run_model("compare_bending.prm",
                              "compare_simulation",
                              {"Run type=simulation",
                               "Method=ddfem",
                               "Coarsening levels=1",
                               "Output/Write VTU=none"},
                              simulation_screen);
  std::cout << "simulation of the same model: exit status " << simulation_status
            << std::endl;
  if (simulation_status != 0)
    std::cout << simulation_screen.str();
  else
    {
      const nlohmann::json &simulated = simulation.at("probes"),
                           &compared  = ddfem_run.at("probes");
      bool same_points                = simulated.size() == compared.size();
      // The largest difference of a displacement component, relative to
      // the largest component.
      double difference = 0, largest = 0;
      for (unsigned int p = 0; same_points && p < simulated.size(); ++p)
        {
          same_points = simulated[p].at("point") == compared[p].at("point");
          for (unsigned int d = 0; d < 3; ++d)
            {
              const double a = simulated[p].at("displacement")[d],
                           b = compared[p].at("displacement")[d];
              difference = ddfem::testing::worst(difference, std::abs(a - b));
              largest    = ddfem::testing::worst(largest, std::abs(a));
            }
        }
      std::cout << "  as many probes, at the same points: "
                << (same_points ? "true" : "false") << std::endl;
      ddfem::testing::check_below("  their displacements against the compare "
                                  "run's, relative difference",
                                  difference / largest,
                                  1e-10);
    }

  // Each speedup is the fastest fine run's wall time of its state (and the
  // direct solver's) over the run's own, and the CSV's numbers are the
  // JSON's (to the CSV's 6 digits), row by row.
  std::map<std::string, double> fastest, direct;
  for (const auto &run : json.at("runs"))
    if (run.at("level") == 0)
      {
        const std::string state = run.at("state");
        const double      time  = run.at("wall_time_s");
        fastest[state] =
          fastest.count(state) ? std::min(fastest[state], time) : time;
        if (run.at("method") == "fine-direct")
          direct[state] = time;
      }
  double speedup_error = 0, csv_error = 0;
  for (unsigned int r = 0; r < json.at("runs").size(); ++r)
    {
      const auto       &run   = json.at("runs")[r];
      const double      time  = run.at("wall_time_s");
      const std::string state = run.at("state");
      speedup_error =
        ddfem::testing::worst(speedup_error,
                              std::abs(run.at("speedup_vs_fine").get<double>() *
                                         time / fastest.at(state) -
                                       1),
                              std::abs(
                                run.at("speedup_vs_fine_direct").get<double>() *
                                  time / direct.at(state) -
                                1));
      for (unsigned int c = 0; c < names.size(); ++c)
        if (run.at(names[c]).is_number())
          {
            const double value = run.at(names[c]);
            csv_error =
              ddfem::testing::worst(csv_error,
                                    std::abs(std::stod(csv_rows[r][c]) -
                                             value) /
                                      std::max(std::abs(value), 1e-300));
          }
        else if (run.at(names[c]).is_null())
          {
            if (!csv_rows[r][c].empty())
              csv_error = 1;
          }
        else
          {
            const auto       &value = run.at(names[c]);
            const std::string text  = value.is_boolean() ?
                                        (value.get<bool>() ? "true" : "false") :
                                        value.get<std::string>();
            if (text != csv_rows[r][c])
              csv_error = 1;
          }
    }
  ddfem::testing::check_below("speedups against the fastest fine run and the "
                              "direct one, relative error",
                              speedup_error,
                              1e-12);
  ddfem::testing::check_below("comparison.csv against comparison.json, "
                              "relative difference",
                              csv_error,
                              1e-5);
  for (const char *file : {"compare/comparison.json",
                           "compare/error_vs_time.png",
                           "compare/fine/solution.pvd",
                           "compare/ddfem-L1/solution.pvd",
                           "compare/naive-L2/solution.pvd"})
    std::cout << file << ": "
              << (std::filesystem::exists(file) ? "written" : "MISSING")
              << std::endl;

  // A quadratic fine model against trilinear coarse ones: coarse models
  // are always trilinear, and the fine runs are compared at the vertices.
  // Its scene name and output directory hold quotes and shell syntax,
  // which must reach neither gnuplot's parser nor a shell.
  const std::string q2_directory = "compare_q2 it's \"$(touch injected)\"";
  std::filesystem::remove_all(q2_directory);
  std::filesystem::remove("injected");
  std::ofstream q2("compare_q2.prm");
  q2 << ddfem::testing::compare_run("bending_q2 it's `touch injected`",
                                    "2, 8, 2",
                                    "0.02, 0.16, 0.02")
     << "subsection Discretization\n"
        "  set Polynomial degree = 2\n"
        "end\n"
        "subsection Comparison\n"
        "  set Methods = naive\n"
        "  set Levels = 1\n"
        "end\n"
     << output(q2_directory, "none");
  q2.close();
  const int status_q2 =
    ddfem::app::run({"compare_q2.prm"}, std::cout, std::cout);
  std::cout << "exit status " << status_q2 << ", plot drawn: "
            << std::filesystem::exists(q2_directory + "/error_vs_time.png")
            << ", command run: " << std::filesystem::exists("injected")
            << std::endl;
  // The plot's title shows the name as it is: quoted, and without gnuplot's
  // enhanced text, which would turn "_q2" into a subscript.
  std::ifstream script(q2_directory + "/error_vs_time.gnuplot");
  for (std::string line; std::getline(script, line);)
    if (line.rfind("set title", 0) == 0)
      std::cout << line << std::endl;

  // The scene's fine model fails (CG may take one iteration only, which
  // a new multigrid hierarchy spends on a reduction of 1e-2, not of
  // 1e-12), the direct one does not: the speedups divide the direct run's time,
  // the failed run has no vertex errors (empty CSV fields), and the others are
  // measured against the direct run.
  std::filesystem::remove_all("compare_failed");
  // The small layered scene with naive L1 and the linear solver @p solver.
  const auto write_prm = [](const std::string &solver,
                            const std::string &directory) {
    std::ofstream prm(directory + ".prm");
    prm << ddfem::testing::compare_run("failed", "2, 8, 2", "0.02, 0.16, 0.02")
        << ddfem::testing::layers("0.04") << "subsection Linear solver\n"
        << solver
        << "end\n"
           "subsection Comparison\n"
           "  set Methods = naive\n"
           "  set Levels = 1\n"
           "end\n"
        << output(directory, "none");
  };
  write_prm("  set Type = cg-amg\n  set Maximum iterations = 1\n"
            "  set Tolerance = 1e-12\n",
            "compare_failed");
  std::ostringstream failed_log;
  const int          status_failed =
    ddfem::app::run({"compare_failed.prm"}, failed_log, failed_log);
  std::cout << "fine model failing: exit status " << status_failed << std::endl;
  std::ifstream failed_csv("compare_failed/comparison.csv");
  std::getline(failed_csv, header);
  const std::vector<std::string> failed_names = split(header);
  for (std::string line; std::getline(failed_csv, line);)
    {
      const std::vector<std::string> fields = split(line);
      // The field of the column @p name (looked up by name, so that new
      // columns do not shift it).
      const auto field = [&](const std::string &name) -> const std::string & {
        return fields.at(
          std::find(failed_names.begin(), failed_names.end(), name) -
          failed_names.begin());
      };
      const std::string &method  = field("method"),
                        &speedup = field("speedup_vs_fine"),
                        &error   = field("mean_vertex_error");
      std::cout << "  " << method << ": converged " << field("converged")
                << ", speedup_vs_fine '"
                << (method == "fine-direct" ? speedup : "...") << "' ("
                << (speedup.empty() ? "empty" : "a number")
                << "), mean_vertex_error '"
                << (method == "naive" ? "..." : error) << "' ("
                << (error.empty() ? "empty" : "a number")
                << "), grid_fit_lower_bound "
                << (field("grid_fit_lower_bound").empty() ? "empty" :
                                                            "a number")
                << std::endl;
    }
  // The JSON has null where the CSV has empty fields, and the converged
  // runs' speedups divide the direct run's wall time by their own.
  std::ifstream        failed_file("compare_failed/comparison.json");
  const nlohmann::json failed_json = nlohmann::json::parse(failed_file);
  double               direct_time = 0;
  for (const auto &run : failed_json.at("runs"))
    if (run.at("method") == "fine-direct")
      direct_time = run.at("wall_time_s");
  for (const auto &run : failed_json.at("runs"))
    {
      const auto &speedup = run.at("speedup_vs_fine");
      std::cout << "  JSON " << run.at("method").get<std::string>()
                << ": mean_vertex_error "
                << (run.at("mean_vertex_error").is_null() ? "null" : "a number")
                << ", grid_fit_lower_bound "
                << (run.at("grid_fit_lower_bound").is_null() ? "null" :
                                                               "a number")
                << ", speedup_vs_fine ";
      if (speedup.is_null())
        std::cout << "null";
      else
        std::cout << "* wall time / the direct run's = 1: "
                  << (std::abs(speedup.get<double>() *
                                 run.at("wall_time_s").get<double>() /
                                 direct_time -
                               1) < 1e-12 ?
                        "yes" :
                        "FAILED");
      std::cout << std::endl;
    }
  // The plot draws the direct run as the fine reference, not the failed
  // one.
  std::ifstream failed_script("compare_failed/error_vs_time.gnuplot");
  std::cout << "  fine runs drawn:";
  for (std::string line; std::getline(failed_script, line);)
    if (line.find("rotate by 90") != std::string::npos)
      std::cout << ' '
                << line.substr(line.find('\''),
                               line.find(" at ") - line.find('\''));
  std::cout << std::endl;

  // Those are the errors of a run whose scene solves with the direct solver.
  std::filesystem::remove_all("compare_direct");
  write_prm("  set Type = direct\n", "compare_direct");
  std::ostringstream direct_log;
  ddfem::app::run({"compare_direct.prm"}, direct_log, direct_log);
  std::ifstream        direct_file("compare_direct/comparison.json");
  const nlohmann::json direct_json = nlohmann::json::parse(direct_file);
  const auto naive = [](const nlohmann::json &runs, const std::string &key) {
    for (const auto &run : runs.at("runs"))
      if (run.at("method") == "naive")
        return run.at(key).get<double>();
    return 0.;
  };
  for (const std::string key :
       {"mean_vertex_error", "max_vertex_error", "grid_fit_mean_vertex_error"})
    std::cout << "  naive " << key
              << " equals that against the scene's direct solver (relative "
                 "difference below 1e-6): "
              << (std::abs(naive(failed_json, key) / naive(direct_json, key) -
                           1) < 1e-6 ?
                    "yes" :
                    "NO")
              << std::endl;
  // The scene's own solver is the direct one: fine-direct does not run it
  // again, and the fine run is the reference of speedup_vs_fine_direct.
  double fine_time = 0;
  for (const auto &run : direct_json.at("runs"))
    if (run.at("method") == "fine")
      fine_time = run.at("wall_time_s");
  for (const auto &run : direct_json.at("runs"))
    std::cout << "  scene solved directly, "
              << run.at("method").get<std::string>() << " ("
              << run.at("linear_solver").get<std::string>()
              << "): speedup_vs_fine_direct * wall time / the fine run's = 1: "
              << (std::abs(run.at("speedup_vs_fine_direct").get<double>() *
                             run.at("wall_time_s").get<double>() / fine_time -
                           1) < 1e-12 ?
                    "yes" :
                    "FAILED")
              << std::endl;

  // gnuplot passes the check before the run (a stand-in first on the PATH
  // that draws nothing with '-e'), but fails to draw the plot: the
  // run stops with gnuplot's error, and keeps its tables and the
  // parameters that made them, but no figure.
  std::filesystem::remove_all("compare_plot_fails");
  std::filesystem::remove_all("failing_gnuplot");
  std::filesystem::create_directory("failing_gnuplot");
  std::ofstream("failing_gnuplot/gnuplot")
    << "#!/bin/sh\ncase \" $* \" in *\" -e \"*) exit 0 ;; esac\n"
       "echo 'set output' > error_vs_time.png\nexit 1\n";
  std::filesystem::permissions("failing_gnuplot/gnuplot",
                               std::filesystem::perms::owner_all);
  const char       *old_path = std::getenv("PATH");
  const std::string path     = old_path != nullptr ? old_path : "";
  setenv("PATH",
         (std::filesystem::absolute("failing_gnuplot").string() + ":" + path)
           .c_str(),
         1);
  write_prm("  set Type = direct\n", "compare_plot_fails");
  std::ostringstream plot_log;
  const int          status_plot =
    ddfem::app::run({"compare_plot_fails.prm"}, plot_log, plot_log);
  setenv("PATH", path.c_str(), 1);
  std::cout << "gnuplot failing: exit status " << status_plot;
  for (const std::string file : {"comparison.json",
                                 "comparison.csv",
                                 "parameters.prm",
                                 "error_vs_time.gnuplot",
                                 "error_vs_time.png"})
    std::cout << ", " << file << " "
              << (std::filesystem::exists("compare_plot_fails/" + file) ?
                    "kept" :
                    "absent");
  std::cout << std::endl;
  std::istringstream plot_lines(plot_log.str());
  for (std::string line; std::getline(plot_lines, line);)
    if (line.rfind("Error", 0) == 0)
      std::cout << "  " << line << std::endl;
}
