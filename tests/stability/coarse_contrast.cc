// The coarse models on the fine solver's stiffness contrast and thin parts:
// contrast 1e6 (compressed by 25 %, where the fine test, contrast_1e6.prm,
// compresses by 15 %: at 25 % the fine model's soft voxels fold,
// tests/stability/inverted.cc, while a coarse model has no nodes inside a
// block to fold them), a plate one voxel thick and a frame of one-voxel
// beams in a cube 90 % void, each solved with the ddfem, naive and average
// coarse models at level 1 (the metamaterials fitted lazily into a fresh
// database per case).
// Every solve must converge with det F > 0 everywhere (coarse_cases.h).
// The plate's centre sinks closer to the fine plate's with ddfem than with
// naive.

#include "coarse_cases.h"

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  ddfem::testing::solve_coarse_cases(
    {{"contrast_1e6",
      "subsection Geometry\n  set Grid size = 4, 4, 4\nend\n"
      "subsection Materials\n  set Palette = E=1e5 nu=0.45; E=1e11 nu=0.45\n"
      "end\n"
      "subsection Layout\n  set Type = random\n"
      "  subsection Random\n    set Materials = 1, 1, 2\n  end\nend\n"
      "subsection Boundary conditions\n"
      "  subsection Condition 1\n    set Type = fixed\n    set Region = z-\n"
      "  end\n"
      "  subsection Condition 2\n    set Type = displacement\n"
      "    set Region = z+\n    set Value = 0; 0; -0.01\n  end\nend\n"
      "subsection Nonlinear solver\n  set Load steps = 5\nend\n",
      {1}},
     // A plate one voxel thick (the bottom half of every block) clamped on
     // two sides under a pressure on its top, which lies inside the blocks.
     {"thin_plate",
      "subsection Geometry\n  set Grid size = 12, 12, 2\n"
      "  set Probe points = 0.06, 0.06, 0.01\nend\n"
      "subsection Materials\n  set Palette = E=1e6 nu=0.45\nend\n"
      "subsection Layout\n  set Material = 0\n"
      "  set Shapes = box 0 0 0 0.12 0.12 0.01 : 1\nend\n"
      "subsection Boundary conditions\n"
      "  subsection Condition 1\n    set Type = fixed\n    set Region = x-\n"
      "  end\n"
      "  subsection Condition 2\n    set Type = fixed\n    set Region = x+\n"
      "  end\n"
      "  subsection Condition 3\n    set Type = pressure\n"
      "    set Region = box 0 0 0.01 0.12 0.12 0.01\n    set Value = 2e4\n"
      "  end\nend\n"
      "subsection Nonlinear solver\n  set Load steps = 5\nend\n",
      {1}},
     // The fine test's frame of one-voxel beams along the edges of a cube,
     // 90 % void.
     {"void_90", "INCLUDE " SOURCE_DIR "/void_90.prm\n", {1}}});

  // The vertical displacement (mm) of the plate's probe, at its centre.
  const auto centre = [](const nlohmann::json &summary) {
    return 1e3 * summary["probes"][0]["displacement"][2].get<double>();
  };
  const auto level_1 = [&centre](const std::string &method) {
    std::ifstream file("thin_plate-" + method + "-1-default/summary.json");
    return centre(nlohmann::json::parse(file));
  };
  const double fine = centre(ddfem::testing::run_successfully("thin_plate.prm",
                                                              "thin_plate-fine",
                                                              {"Method=fine"}));
  const double ddfem_l1 = level_1("ddfem"), naive_l1 = level_1("naive");
  std::cout << "thin_plate, centre (mm): fine " << fine << ", ddfem L1 "
            << ddfem_l1 << ", naive L1 " << naive_l1
            << "; ddfem closer to fine than naive: " << std::boolalpha
            << (std::abs(ddfem_l1 - fine) < std::abs(naive_l1 - fine))
            << std::endl;
}
