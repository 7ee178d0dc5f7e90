// Every model that rotates on a known answer at a stiffness contrast of
// 1e6 and near incompressibility: a bar of 4 x 8 x 4 voxels in layers one
// voxel thick of E = 1e5 Pa, nu = 0.499 and E = 1e11 Pa, nu = 0.3, whose
// y- face is turned by 150 degrees about (1, 2, 2)/3 through its centre
// and which is otherwise free and unloaded, rotates rigidly. Fine Q1,
// naive, average and ddfem at levels 1 and 2, and corotated DG must follow
// the rotation to round-off with no strain: the Neo-Hookean energy and
// the metamaterials' springs (sqrt(v^T F^T F v) - 1) vanish at F = R, and
// corotated DG warps each element by its rotation. The coarse and fine
// models' Newton iterations run to round-off (error below 1e-8); DG's
// fixed-point iteration stops at its tolerance, a change of 1e-8 relative
// to the solution (error below 1e-6: it converges slowly at this contrast,
// and does not reach 1e-12 in 50 iterations).

#include <filesystem>
#include <fstream>

#include "../tests.h"

namespace
{
  /// The parameter text of the bar, into the database "rotation.h5".
  const std::string bar =
    "subsection Geometry\n  set Grid size = 4, 8, 4\n"
    "  set Voxel size = 0.01\n"
    "  set Probe points = 0.04, 0.08, 0.04; 0.01, 0.05, 0.03\nend\n"
    "subsection Materials\n"
    "  set Palette = E=1e5 nu=0.499; E=1e11 nu=0.3\nend\n"
    "subsection Layout\n  set Type = layers\n  subsection Layers\n"
    "    set Axis = y\n    set Thickness = 0.01\n    set Materials = 1, 2\n"
    "  end\nend\n"
    "subsection Boundary conditions\n  subsection Condition 1\n"
    "    set Type = rotation\n    set Region = y-\n"
    "    set Axis = 1, 2, 2\n    set Angle = 150\n  end\nend\n"
    "subsection Nonlinear solver\n  set Load steps = 6\n"
    "  set Newton tolerance = 1e-12\nend\n"
    "subsection DG\n  set Formulation = corotated\n  set Load steps = 6\n"
    "end\n"
    "subsection Output\n  set Screen timings = false\n"
    "  set Write VTU = none\nend\n"
    "subsection Database\n  set File = rotation.h5\n"
    "  subsection Sampling\n    set Patterns = 40\n"
    "    set Stretch directions = 40\n  end\nend\n";

  /// The displacement of the rigid rotation at @p x, from the matrix form
  /// of the rotation (the code under test uses the vector form).
  dealii::Tensor<1, 3>
  rotation(const dealii::Point<3> &x)
  {
    const dealii::Tensor<1, 3> r = x - dealii::Point<3>(0.02, 0, 0.02);
    return ddfem::testing::rotation_about(
             dealii::Tensor<1, 3>({1. / 3, 2. / 3, 2. / 3}), 150) *
             r -
           r;
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  ddfem::testing::remove_database("rotation.h5");
  std::ofstream("rotation.prm") << bar;

  const std::vector<std::pair<std::string, std::vector<std::string>>> models = {
    {"fine Q1", {"Method=fine"}},
    {"naive L1", {"Method=naive", "Coarsening levels=1"}},
    {"naive L2", {"Method=naive", "Coarsening levels=2"}},
    {"average L1", {"Method=average", "Coarsening levels=1"}},
    {"average L2", {"Method=average", "Coarsening levels=2"}},
    {"ddfem L1", {"Method=ddfem", "Coarsening levels=1"}},
    {"ddfem L2", {"Method=ddfem", "Coarsening levels=2"}},
    {"DG IP corotated", {"Method=dg"}}};
  for (const auto &[name, settings] : models)
    {
      std::ostringstream screen;
      const auto [status, summary] = ddfem::testing::run_model(
        "rotation.prm", "rotation-" + name, settings, screen);
      std::cout << name << ": exit status " << status << std::endl;
      if (status != 0)
        {
          std::cout << screen.str();
          continue;
        }

      // The probes' largest error, relative to 0.1 m: the rotation moves
      // the bar's points by up to 2 sin(75 degrees) times their distance
      // from the centre of its y- face, up to 0.16 m.
      double error = 0;
      for (const auto &probe : summary.at("probes"))
        {
          const std::vector<double> x = probe.at("point"),
                                    u = probe.at("displacement");
          const dealii::Tensor<1, 3> exact =
            rotation(dealii::Point<3>(x[0], x[1], x[2]));
          for (unsigned int d = 0; d < 3; ++d)
            error = ddfem::testing::worst(error, std::abs(u[d] - exact[d]));
        }
      // The number of probes, so that an empty list cannot pass.
      ddfem::testing::check_below(
        "  probe displacement error (" +
          std::to_string(summary.at("probes").size()) + " probes) / 0.1 m",
        error / 0.1,
        name.substr(0, 2) == "DG" ? 1e-6 : 1e-8);
      // DG reports no strain; every other model must.
      if (name.substr(0, 2) != "DG")
        ddfem::testing::check_below(
          "  largest principal strain of a cell",
          std::abs(summary.at("principal_strain").at("max").get<double>()),
          1e-8);
    }
}
