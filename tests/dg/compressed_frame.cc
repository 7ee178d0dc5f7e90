// Corotated DG at a buckling load: the frame of one-voxel beams of
// tests/stability/void_90.prm (default palette) pressed by 15 %, probed at
// a column's mid-height (doc/dg.md, "Compressed past buckling"):
// - the fine model (CG Q1, Neo-Hookean) buckles the columns: the probe
//   moves more than 10 mm sideways;
// - corotated DG (FE_DGQ(1), 12 load steps) stalls where the columns reach
//   their buckling load: with the default 50 iterations it stops at load
//   step 6 of 12 with a message that names the buckling load, exit 1 and
//   no summary;
// - with 200 iterations it passes the stall and follows the unbuckled
//   state in fewer than 400 linear solves: the probe moves less than
//   0.1 mm sideways. (It passes because
//   the relaxation factor is bounded; unbounded, the change stayed at
//   1.8e-4 in a run with 100 iterations.)

#include <ddfem/app/application.h>

#include <iomanip>

#include "../tests.h"
#include "probes.h"

using namespace ddfem;

namespace
{
  /// Runs the pressed frame with @p settings into the directory @p name;
  /// prints the exit status, and the probe's sideways displacement in mm
  /// (returned; NaN if the run wrote no summary) or the start of the error
  /// message and whether it names the buckling load.
  double
  run(const std::string &name, const std::vector<std::string> &settings)
  {
    std::vector<std::string> all = {"Geometry/Probe points=0.005, 0.005, 0.05",
                                    "Output/Write VTU=none"};
    all.insert(all.end(), settings.begin(), settings.end());
    std::ostringstream screen;
    const auto [status, summary] = testing::run_model(
      std::string(SOURCE_DIR) + "/../stability/void_90.prm", name, all, screen);
    std::cout << name << ": exit status " << status;
    if (summary.is_null())
      {
        const std::string text  = screen.str();
        const std::size_t start = text.find("Error: ");
        std::cout << ", no summary.json" << std::endl;
        if (start == std::string::npos)
          std::cout << "  no error message" << std::endl;
        else
          std::cout << "  "
                    << text.substr(start, text.find(':', start + 7) - start)
                    << std::endl
                    << "  names the buckling load: " << std::boolalpha
                    << (text.find("buckling load", start) != std::string::npos)
                    << std::endl;
        return std::numeric_limits<double>::quiet_NaN();
      }
    const dealii::Tensor<1, 3> u = testing::probe_displacements(summary)[0];
    const double               sideways = 1e3 * std::hypot(u[0], u[1]);
    std::cout << ", probe " << std::setprecision(3) << sideways
              << " mm sideways" << std::setprecision(6) << std::endl;
    // The count at the stall moves with round-off (280 and 279 on two
    // hosts), so only its bound is compared.
    if (summary.contains("linear_solves"))
      testing::check_below("  linear solves",
                           summary.at("linear_solves").get<double>(),
                           400);
    return sideways;
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const std::vector<std::string>           corotated = {"Method=dg",
                                                        "DG/Formulation=corotated",
                                                        "DG/Load steps=12"};

  const double fine = run("fine", {"Method=fine"});
  AssertThrow(fine > 10, dealii::ExcMessage("The fine model did not buckle."));

  run("dg", corotated);
  std::vector<std::string> more = corotated;
  more.push_back("DG/Corotation iterations=200");
  testing::check_below("dg, 200 iterations: sideways (mm)",
                       run("dg_200", more),
                       0.1);
}
