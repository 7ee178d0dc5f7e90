// The coarse models on a 50 % compression of a layered cube clamped on its
// floor (the fine test compression_50.prm presses the same cube on a
// sliding floor; the clamped floor adds the shear of the bulge): at level 1 (also with the level-1 point offset 0.45, which softens
// the element in bending) and a larger cube at level 2, each solved with
// the ddfem, naive and average coarse models (the metamaterials fitted
// lazily into a fresh database per case and level-1 offset).
// Every solve must converge with det F > 0 everywhere (coarse_cases.h).

#include "coarse_cases.h"
#include "layered_cube.h"

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  ddfem::testing::solve_coarse_cases(
    {{"compression_50_clamped",
      ddfem::testing::compressed_cube(4, 0.5),
      {1},
      {"default", "0.45"}},
     {"compression_50_clamped_8", ddfem::testing::compressed_cube(8, 0.5), {2}}});
}
