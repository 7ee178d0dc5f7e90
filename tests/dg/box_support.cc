// A box region holds every node and face it contains, for DG as for CG.
// A uniform cantilever of 16 voxel layers held by a box around its first
// layer (both of the layer's node planes) is a cantilever of 15 layers
// clamped at its end: the two tips move alike. CG and DG with strong
// conditions hold the same nodes in both, so they agree to the solver's
// tolerance. Weak (Nitsche) conditions hold the first layer's faces,
// interior ones included, by a penalty, so the held layer gives a little:
// the tips are 0.22 % apart at eta = 10. DG held only the boundary faces in
// the box before, so the layer's inner node plane was free inside: the
// box-held tip moved 2.6 % more than the short bar's with strong conditions
// (automatic penalty, eta = 2) and 3.5 % more with weak ones.

#include <iomanip>

#include "../tests.h"
#include "probes.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  /// The tip displacement of a run of prm/default.prm, made uniform, with
  /// @p length voxel layers along y held on @p region, with the settings
  /// @p extra (testing::run_model()), written to @p directory.
  Tensor<1, 3>
  tip(const std::string              &directory,
      const unsigned int              length,
      const std::string              &region,
      const std::vector<std::string> &extra)
  {
    std::vector<std::string> settings = {
      "Output/Write VTU=none",
      "Layout/Type=uniform",
      "Layout/Material=2",
      "Geometry/Grid size=4, " + std::to_string(length) + ", 4",
      "Geometry/Probe points=0.04, " + std::to_string(0.02 * length) + ", 0.04",
      "Boundary conditions/Condition 1/Region=" + region};
    settings.insert(settings.end(), extra.begin(), extra.end());
    return testing::probe_displacements(
      testing::run_successfully(std::string(SOURCE_DIR) +
                                  "/../../prm/default.prm",
                                directory,
                                settings))[0];
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  for (const auto &[name, settings, bound] :
       {std::make_tuple("CG", std::vector<std::string>{"Method=fine"}, 1e-7),
        std::make_tuple("DG, strong conditions",
                        std::vector<std::string>{"Method=dg",
                                                 "DG/Dirichlet=strong"},
                        1e-9),
        std::make_tuple("DG, weak conditions",
                        std::vector<std::string>{"Method=dg", "DG/Penalty=10"},
                        5e-3)})
    {
      const Tensor<1, 3> held_by_box =
        tip("box", 16, "box 0 0 0 0.08 0.02 0.08", settings);
      const Tensor<1, 3> clamped = tip("short", 15, "y-", settings);
      std::cout << name << ": tip u_z " << std::setprecision(4)
                << 1e3 * clamped[2] << " mm clamped at the end" << std::endl;
      testing::check_below("  held by a box around the first layer instead: "
                           "tips apart by (relative)",
                           (held_by_box - clamped).norm() / clamped.norm(),
                           bound);
    }
}
