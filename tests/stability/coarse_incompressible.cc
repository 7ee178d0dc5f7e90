// The coarse models near incompressibility: soft and stiff voxels at
// random, both at nu = 0.49, pressed by 30 % on a sliding floor, solved
// with the ddfem, naive and average coarse models at level 1 (the
// metamaterials fitted lazily into a fresh database).
// Every solve must converge with det F > 0 everywhere (coarse_cases.h).

#include "coarse_cases.h"

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  ddfem::testing::solve_coarse_cases(
    {{"nu_049",
      "subsection Geometry\n  set Grid size = 4, 4, 4\nend\n"
      "subsection Materials\n  set Palette = E=1e5 nu=0.49; E=1e7 nu=0.49\n"
      "end\n"
      "subsection Layout\n  set Type = random\n"
      "  subsection Random\n    set Materials = 1, 2\n  end\nend\n"
      "subsection Boundary conditions\n"
      "  subsection Condition 1\n    set Type = sliding\n    set Region = z-\n"
      "  end\n"
      "  subsection Condition 2\n    set Type = displacement\n"
      "    set Region = z+\n    set Value = free; free; -0.012\n  end\n"
      "  subsection Condition 3\n    set Type = fixed\n"
      "    set Region = box 0 0 0 0 0 0\n  end\n"
      "  subsection Condition 4\n    set Type = sliding\n    set Region = x-\n"
      "  end\nend\n"
      "subsection Nonlinear solver\n  set Load steps = 5\nend\n",
      {1}}});
}
