// DG against CG on the stability scenes of doc/dg.md, both with degree 2:
// each scene test's prm run with IP FE_DGQ(2), and with 'Method = fine' and
// FE_Q(2) in one load step. The probes' displacements along z must agree:
// - contrast_1e6.prm (stiffness contrast 1e6, 1 % compression): within
//   3 % at both probes. At degree 1 the second probe, inside the random
//   mix, moves 30 % less than at degree 2, with CG as with DG;
// - nu_0499.prm (nu = 0.499, a cantilever): within 4 %; CG Q2 locks a
//   little (doc/dg.md, "Near incompressibility").

#include <ddfem/app/application.h>

#include <fstream>
#include <iomanip>

#include "../tests.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  /// The z displacements of the probes of a run of @p prm with @p extra
  /// settings, written to @p directory.
  std::vector<double>
  probes_z(const std::string              &prm,
           const std::string              &directory,
           const std::vector<std::string> &extra)
  {
    std::vector<std::string> arguments = {std::string(SOURCE_DIR) + "/" + prm,
                                          "--set",
                                          "Output/Output directory=" +
                                            directory};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    std::ostringstream screen;
    const int          status = app::run(arguments, screen, screen);
    AssertThrow(status == 0, ExcMessage(screen.str()));
    std::ifstream        file(directory + "/summary.json");
    const nlohmann::json summary = nlohmann::json::parse(file);
    std::vector<double>  z;
    for (const auto &probe : summary["probes"])
      z.push_back(probe["displacement"][2].get<double>());
    return z;
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  for (const auto &[prm, tolerance] : {std::make_pair("contrast_1e6.prm", 0.03),
                                       std::make_pair("nu_0499.prm", 0.04)})
    {
      const std::vector<double> dg =
        probes_z(prm, "dg", {"--set", "Discretization/Polynomial degree=2"});
      const std::vector<double> cg =
        probes_z(prm,
                 "cg",
                 {"--set",
                  "Method=fine",
                  "--set",
                  "Discretization/Polynomial degree=2",
                  "--set",
                  "Nonlinear solver/Load steps=1"});
      std::cout << prm << ":" << std::endl;
      for (unsigned int p = 0; p < dg.size(); ++p)
        std::cout << "  probe " << p + 1
                  << ": u_z(DG Q2) = " << std::setprecision(4) << 1e3 * dg[p]
                  << " mm, u_z(CG Q2) = " << 1e3 * cg[p] << " mm, ratio "
                  << dg[p] / cg[p] << std::setprecision(6) << std::endl;
      for (unsigned int p = 0; p < dg.size(); ++p)
        testing::check_below("  probe " + std::to_string(p + 1) +
                               ", |u_z(DG Q2) / u_z(CG Q2) - 1|",
                             std::abs(dg[p] / cg[p] - 1),
                             tolerance);
    }
}
