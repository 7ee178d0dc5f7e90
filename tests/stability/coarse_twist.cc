// The coarse models on the fine solver's 180 degree twist of a layered bar
// (twist_180.prm) on 4 x 12 x 4 voxels, as the fine test's 3 x 12 x 3 grid
// cannot be coarsened, and with layers 3 voxels thick (the fine test's are
// 2), so that a third of the level-1 blocks hold two materials and every
// level-2 block does; solved with the ddfem, naive and average coarse models at
// level 1 (also with the level-1 point offset 0.45, which softens the element
// in bending) and at level 2, whose default point offset softens the element in
// bending (the metamaterials fitted lazily into a fresh database per level-1
// offset).
// Every solve must converge with det F > 0 everywhere (coarse_cases.h).

#include "coarse_cases.h"

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  ddfem::testing::solve_coarse_cases(
    {{"twist_180",
      "subsection Geometry\n  set Grid size = 4, 12, 4\n"
      "  set Probe points = 0.04, 0.06, 0.04\nend\n"
      "subsection Layout\n  set Type = layers\n"
      "  subsection Layers\n    set Thickness = 0.03\n"
      "    set Materials = 1, 2\n  end\nend\n"
      "subsection Boundary conditions\n"
      "  subsection Condition 1\n    set Type = fixed\n    set Region = y-\n"
      "  end\n"
      "  subsection Condition 2\n    set Type = rotation\n    set Region = y+\n"
      "    set Axis = 0, 1, 0\n    set Angle = 180\n  end\nend\n"
      "subsection Nonlinear solver\n  set Load steps = 12\nend\n",
      {1, 2},
      {"default", "0.45"}}});
}
