// Stiffness contrast 1e6 beyond what the voxels can follow: the random cube
// of stiff and soft voxels of contrast_1e6.prm compressed by 25 % instead of
// 15 %. The soft voxels between stiff ones fold: at load factor 0.8
// Newton's method converges to a state in which det F is positive at every
// quadrature point but negative at a vertex of a cell. The solve must stop
// there with a message that names the cell (exit status 1), keep the last
// state that is a deformation, and say so in summary.json. A coarse model
// (naive, level 1) compressed by 70 % stops the same way, with a message
// that points to the coarsening.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "../tests.h"
#include "layered_cube.h"

namespace
{
  /**
   * Runs ddfem on the parameter file @p prm with the settings @p settings
   * into @p directory; prints its exit status, the lines that say where it
   * stopped, and what summary.json says of the state it kept.
   */
  void
  run_and_report(const std::string              &prm,
                 const std::string              &directory,
                 const std::vector<std::string> &settings)
  {
    std::ostringstream log;
    const auto [status, summary] =
      ddfem::testing::run_model(prm, directory, settings, log);
    std::cout << "exit status " << status << std::endl;
    std::istringstream lines(log.str());
    for (std::string line; std::getline(lines, line);)
      if (line.find("Stopped") != std::string::npos ||
          line.find("load steps and") != std::string::npos)
        std::cout << line << std::endl;
    std::cout << "summary.json: converged " << summary.at("converged")
              << ", load steps kept " << summary.at("load_steps")
              << ", min_vertex_J of the last kept state "
              << summary.at("min_vertex_J").get<double>()
              << ", coarsening_time_s "
              << (summary.at("coarsening_time_s").is_null() ? "null" :
                                                              "a number")
              << std::endl;
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  std::ofstream("inverted.prm")
    << "subsection Geometry\n  set Grid size = 4, 4, 4\nend\n"
       "subsection Materials\n"
       "  set Palette = E=1e5 nu=0.45; E=1e11 nu=0.45\n"
       "end\n"
       "subsection Layout\n  set Type = random\n"
       "  subsection Random\n    set Materials = 1, 1, 2\n  end\nend\n"
       "subsection Boundary conditions\n"
       "  subsection Condition 1\n    set Type = fixed\n"
       "    set Region = z-\n  end\n"
       "  subsection Condition 2\n    set Type = displacement\n"
       "    set Region = z+\n    set Value = 0; 0; -0.01\n  end\nend\n"
       "subsection Nonlinear solver\n  set Load steps = 5\nend\n"
       "subsection Output\n  set Screen timings = false\n"
       "  set Write VTU = none\nend\n";
  std::cout << "Fine model, contrast 1e6, compressed by 25 %:" << std::endl;
  run_and_report("inverted.prm", "inverted", {});

  // A coarse model folds too, at a larger compression: layers of one
  // voxel of E = 1e5 and 1e7 Pa, compressed by 70 % in 10 load steps, with
  // the unfitted element at level 1. Its message points to the coarsening.
  std::ofstream("folded.prm")
    << ddfem::testing::compressed_cube(4, 0.7)
    << "subsection Output\n  set Screen timings = false\n"
       "  set Write VTU = none\nend\n";
  std::cout << "Naive level 1, layers, compressed by 70 %:" << std::endl;
  run_and_report("folded.prm",
                 "folded",
                 {"Method=naive", "Coarsening levels=1"});
}
