// Corotated DG at a buckling load: the frame of one-voxel beams of
// tests/stability/void_90.prm (default palette, FE_DGQ(1)) pressed by 15 %
// in 12 load steps, probed at a column's mid-height (doc/dg.md, "Compressed
// past buckling"):
// - the fine model (CG Q1, Neo-Hookean) buckles the columns: the probe
//   moves more than 10 mm sideways;
// - the corotated iteration stalls where the columns reach their buckling
//   load: with the default 50 iterations it stops at load step 6 of 12
//   with a message that names the stall, exit 1 and no summary;
// - with 200 iterations it passes the stall (its relaxation factor is
//   bounded: unbounded, it stayed at a change of 1.8e-4) and follows the
//   unbuckled state: the probe moves less than 0.1 mm sideways.

#include <ddfem/app/application.h>

#include <iomanip>

#include "../tests.h"

using namespace ddfem;

namespace
{
  /// Runs the pressed frame with @p settings into @p directory; prints the
  /// exit status, and the probe's sideways displacement in mm (returned) or
  /// the start of the error message.
  double
  run(const std::string &name, const std::vector<std::string> &settings)
  {
    std::vector<std::string> all = {"DG/Load steps=12",
                                    "Geometry/Probe points=0.005, 0.005, 0.05",
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
        std::cout << ", no summary.json" << std::endl
                  << "  "
                  << text.substr(start, text.find(':', start + 7) - start)
                  << std::endl;
        return std::numeric_limits<double>::quiet_NaN();
      }
    const auto  &u = summary.at("probes").at(0).at("displacement");
    const double sideways =
      1e3 * std::hypot(u.at(0).get<double>(), u.at(1).get<double>());
    std::cout << ", probe " << std::setprecision(3) << sideways
              << " mm sideways";
    if (summary.contains("linear_solves"))
      std::cout << ", " << summary.at("linear_solves") << " linear solves";
    std::cout << std::setprecision(6) << std::endl;
    return sideways;
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const std::vector<std::string> dg = {"Method=dg", "DG/Formulation=corotated"};

  const double fine = run("fine", {"Method=fine"});
  AssertThrow(fine > 10, dealii::ExcMessage("The fine model did not buckle."));

  run("dg", dg);
  std::vector<std::string> more = dg;
  more.push_back("DG/Corotation iterations=200");
  testing::check_below("dg, 200 iterations: sideways (mm)",
                       run("dg_200", more),
                       0.1);
}
