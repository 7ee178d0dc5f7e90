// Level-1 ddfem on a porous part of two materials: a 12 x 12 x 12 voxel
// cube whose voxels are drawn at random from void (1 in 7) and the
// palette's E = 1e5 and 1e7 (3 in 7 each), clamped at the bottom and
// pressed on top. Most of its 2x2x2 blocks are mixed and hold a void
// voxel. A free block of that kind deforms through its soft voxels; in
// the part its stiff voxels also carry load through the neighbouring
// blocks. Sampled by force patterns on the free block (sampler revisions 1
// to 8), the fits made the stiff voxels up to 119 times too soft:
// ddfem's mean vertex error was 8.3 times naive's (2.16e-2 against
// 2.59e-3, with the parameters below). Since revision 9 such blocks get
// embedded samples, as mixed blocks without void do, where their solid
// voxels are joined through faces: 0.53 times naive's.

#include "ddfem_against_naive.h"

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  ddfem::testing::remove_database("porous.h5");
  // 42 % above the measured 0.53; the free-block fits gave 8.3.
  ddfem::testing::check_ddfem_against_naive(
    "set Run type = compare\n"
    "subsection Geometry\n"
    "  set Grid size  = 12, 12, 12\n"
    "  set Voxel size = 0.01\n"
    "end\n"
    "subsection Materials\n"
    "  set Palette = E=1e5 nu=0.45; E=1e7 nu=0.45\n"
    "end\n"
    "subsection Layout\n"
    "  set Type = random\n"
    "  subsection Random\n"
    "    set Materials = 0, 1, 2, 1, 2, 1, 2\n"
    "    set Seed      = 1\n"
    "  end\n"
    "end\n"
    "subsection Boundary conditions\n"
    "  subsection Condition 1\n"
    "    set Type   = fixed\n"
    "    set Region = z-\n"
    "  end\n"
    "  subsection Condition 2\n"
    "    set Type   = traction\n"
    "    set Region = z+\n"
    "    set Value  = 0; 0; -3e4\n"
    "  end\n"
    "end\n"
    "subsection Nonlinear solver\n"
    "  set Load steps = 2\n"
    "end\n"
    "subsection Database\n"
    "  set File = porous.h5\n"
    "  subsection Sampling\n"
    "    set Patterns           = 30\n"
    "    set Magnitudes         = 2\n"
    "    set Stretch directions = 20\n"
    "  end\n"
    "end\n",
    "porous",
    0.75);
}
