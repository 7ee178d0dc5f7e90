// Run type = compare on a small version of the bending scene: fine (with
// multigrid CG and with the direct solver), ddfem, naive and average at
// coarsening levels 1 and 2, the metamaterials fitted lazily into a fresh
// database. The screen table (without timings) is compared; the files the
// run writes are checked for their columns. A second, smaller run compares
// a quadratic fine model with the trilinear naive one.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "../tests.h"

namespace
{
  /// The start of a compare run's parameters: a cantilever of @p grid
  /// voxels of 0.02 m pulled down at its tip, probed at @p probe.
  std::string
  compare_run(const std::string &name,
              const std::string &grid,
              const std::string &probe)
  {
    return "set Run type = compare\nset Scene name = " + name + "\n" +
           ddfem::testing::cantilever(grid, "0; 0; -2000") +
           "subsection Geometry\n  set Voxel size = 0.02\n"
           "  set Probe points = " +
           probe + "\nend\n";
  }

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
  for (const char *file :
       {"compare.h5", "compare.h5.journal", "compare.h5.level2"})
    std::filesystem::remove(file);
  std::filesystem::remove_all("compare");

  // prm/bending.prm with half the voxels per direction, and layers of three
  // voxels: they cut through the 2x2x2 blocks, so that ddfem, naive and
  // average differ at level 1.
  std::ofstream prm("compare_bending.prm");
  prm << compare_run("bending", "4, 16, 4", "0.04, 0.32, 0.04")
      << "subsection Materials\n"
         "  set Palette = E=1e5 nu=0.45; E=1e6 nu=0.45; E=1e7 nu=0.45\n"
         "end\n"
         "subsection Layout\n"
         "  set Type = layers\n"
         "  subsection Layers\n"
         "    set Axis = y\n"
         "    set Materials = 1, 2, 3\n"
         "    set Thickness = 0.06\n"
         "  end\n"
         "end\n"
         "subsection Database\n"
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
  unsigned int lines = 0;
  for (std::string line; std::getline(csv, line);)
    ++lines;
  std::cout << "comparison.csv rows: " << lines << std::endl;

  // comparison.json has every column of the CSV in every run.
  std::ifstream         json_file("compare/comparison.json");
  const nlohmann::json  json = nlohmann::json::parse(json_file);
  std::set<std::string> missing;
  std::stringstream     columns(header);
  for (std::string column; std::getline(columns, column, ',');)
    for (const auto &run : json.at("runs"))
      if (!run.contains(column))
        missing.insert(column);
  std::cout << "comparison.json runs: " << json.at("runs").size()
            << ", CSV columns missing in them:";
  for (const std::string &column : missing)
    std::cout << ' ' << column;
  std::cout << (missing.empty() ? " none" : "") << std::endl;
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
  q2 << compare_run("bending_q2 it's `touch injected`",
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
}
