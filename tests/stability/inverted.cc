// Stiffness contrast 1e6 beyond what the voxels can follow: the random cube
// of stiff and soft voxels of contrast_1e6.prm compressed by 25 % instead of
// 15 %. The soft voxels between stiff ones fold: at load factor 0.8
// Newton's method converges to a state in which det F is positive at every
// quadrature point but negative at a vertex of a cell. The solve must stop
// there with a message that names the cell (exit status 1), keep the last
// state that is a deformation, and say so in summary.json.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "../tests.h"

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  std::filesystem::remove_all("inverted");
  std::ofstream prm("inverted.prm");
  prm << "subsection Geometry\n  set Grid size = 4, 4, 4\nend\n"
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
         "subsection Output\n  set Output directory = inverted\n"
         "  set Screen timings = false\n  set Write VTU = none\nend\n";
  prm.close();

  std::ostringstream log;
  const int          status = ddfem::app::run({"inverted.prm"}, log, log);
  std::cout << "exit status " << status << std::endl;
  std::istringstream lines(log.str());
  for (std::string line; std::getline(lines, line);)
    if (line.find("Stopped") != std::string::npos ||
        line.find("load steps and") != std::string::npos)
      std::cout << line << std::endl;

  std::ifstream        file("inverted/summary.json");
  const nlohmann::json summary = nlohmann::json::parse(file);
  std::cout << "summary.json: converged " << summary.at("converged")
            << ", load steps kept " << summary.at("load_steps")
            << ", min_vertex_J of the last kept state "
            << summary.at("min_vertex_J").get<double>()
            << ", coarsening_time_s of the fine model "
            << summary.at("coarsening_time_s") << std::endl;
}
