// DG on a part that is 90 % void, at stiffness contrast 1e6 and nu = 0.499:
// the frame of tests/stability/void_90.prm (the twelve edges of a cube as
// beams one voxel thick, 104 of 1000 voxels solid) with soft, nearly
// incompressible columns (E = 1e5 Pa, nu = 0.499) between stiff top and
// bottom frames (E = 1e11 Pa), the bottom clamped. IP FE_DGQ(2) with the
// automatic penalty against CG FE_Q(2), probed on a column's axis at
// mid-height and on its side at 30 % of the height:
// - only the solid voxels carry DoFs (104 cells of 81 DoFs), and the
//   automatic penalty makes K positive definite;
// - the lid pressed down by 1e-5 m (linear DG, one CG load step): by the
//   frame's mirror symmetry about z = 0.05 m, linear DG's u_z at
//   mid-height (the mean of the two cells that share the face there) is
//   exactly half the lid's (1e-10); at the side the
//   displacements of DG and CG agree within 1 %;
// - the lid turned by 30 degrees about the vertical axis (corotated DG
//   against Neo-Hookean CG, 6 load steps each): the columns bend into an S
//   and the lid moves them 16.5 mm sideways at mid-height; the probes'
//   displacements agree within 3 % of their length. The number of
//   corotated solves is printed: before the iteration was relaxed
//   (Aitken), it ran out of 50 iterations at the fourth load step (and of
//   300 at the fifth).

#include <ddfem/app/application.h>

#include <iomanip>

#include "../tests.h"
#include "probes.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  /// The frame with the materials above (void_90.prm's columns are
  /// material 1, its frames material 3; material 2 is not used) and degree
  /// 2, without VTU files.
  const std::vector<std::string> frame = {
    "Materials/Palette=E=1e5 nu=0.499; E=1e6 nu=0.45; E=1e11 nu=0.45",
    "Discretization/Polynomial degree=2",
    "Output/Write VTU=none",
    "Geometry/Probe points=0.005, 0.005, 0.05; 0.01, 0.005, 0.03"};

  /// Runs the frame with the settings @p settings added into @p directory,
  /// asserts that it succeeds, and returns its summary.json.
  nlohmann::json
  run(const std::string &directory, const std::vector<std::string> &settings)
  {
    std::vector<std::string> all = frame;
    all.insert(all.end(), settings.begin(), settings.end());
    return testing::run_successfully(
      std::string(SOURCE_DIR) + "/../stability/void_90.prm", directory, all);
  }

  /// Prints the displacements of both runs' probes @p probes in mm, and
  /// checks that they differ by less than @p tolerance times the CG one's
  /// length.
  void
  compare_probes(const nlohmann::json            &dg,
                 const nlohmann::json            &cg,
                 const std::vector<unsigned int> &probes,
                 const double                     tolerance)
  {
    for (const unsigned int p : probes)
      {
        const Tensor<1, 3> u_dg = testing::probe_displacements(dg)[p],
                           u_cg = testing::probe_displacements(cg)[p];
        std::cout << "  probe " << p + 1 << ": u(DG) = ("
                  << std::setprecision(4) << 1e3 * u_dg << ") mm, u(CG) = ("
                  << 1e3 * u_cg << ") mm" << std::setprecision(6) << std::endl;
        testing::check_below("  probe " + std::to_string(p + 1) +
                               ", |u(DG) - u(CG)| / |u(CG)|",
                             (u_dg - u_cg).norm() / u_cg.norm(),
                             tolerance,
                             2);
      }
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  const double      lid = 1e-5;
  const std::string pressed =
    "Boundary conditions/Condition 2/Value=0; 0; -" + std::to_string(lid);
  const nlohmann::json dg = run("dg_pressed", {"Method=dg", pressed});
  std::cout << "DG: " << dg.at("cells") << " cells, " << dg.at("dofs")
            << " DoFs, penalty " << dg.at("penalty") << ", K "
            << dg.at("definiteness").get<std::string>() << std::endl;
  AssertThrow(dg.at("cells") == 104 && dg.at("dofs") == 104 * 81,
              ExcMessage("DoFs outside the solid voxels"));

  std::cout << "Lid pressed down by 0.01 mm, linear DG against CG:"
            << std::endl;
  testing::check_below("  probe 1, |u_z(DG) / u_z(lid) - 1/2|",
                       std::abs(testing::probe_displacements(dg)[0][2] / -lid -
                                0.5),
                       1e-10); // round-off: not pinned
  const nlohmann::json cg =
    run("cg_pressed",
        {"Method=fine", "Nonlinear solver/Load steps=1", pressed});
  compare_probes(dg, cg, {1}, 0.01);

  std::cout << "Lid turned by 30 degrees, corotated DG against CG:"
            << std::endl;
  const std::vector<std::string> turned = {
    "Boundary conditions/Condition 2/Type=rotation",
    "Boundary conditions/Condition 2/Axis=0, 0, 1",
    "Boundary conditions/Condition 2/Angle=30",
    "Boundary conditions/Condition 2/Center=auto"};
  std::vector<std::string> dg_turned = {"Method=dg",
                                        "DG/Formulation=corotated",
                                        "DG/Load steps=6"};
  // CG solved to 1e-11: at the default 1e-8 the soft columns' probe
  // moved by 4e-4 of its displacement with the load path's predictor.
  std::vector<std::string> cg_turned = {
    "Method=fine",
    "Nonlinear solver/Load steps=6",
    "Nonlinear solver/Newton tolerance=1e-11"};
  dg_turned.insert(dg_turned.end(), turned.begin(), turned.end());
  cg_turned.insert(cg_turned.end(), turned.begin(), turned.end());
  const nlohmann::json dg_twist = run("dg_turned", dg_turned);
  std::cout << "  corotated DG: " << dg_twist.at("linear_solves")
            << " linear solves in 6 load steps" << std::endl;
  compare_probes(dg_twist, run("cg_turned", cg_turned), {0, 1}, 0.03);
}
