// Level-1 ddfem on the shipped scene prm/lattice.prm: a cantilever of
// 8 x 32 x 8 voxels of one material with holes in a pattern of 4 x 4
// voxels across the bar (y-z), repeated along it and through its width. A
// quarter of its 2x2x2 blocks hold two solid columns that touch only along
// an edge: mechanism blocks, in a part that is connected through its
// faces. Their fits depend on whether the sampler loads the hinge. With
// only the hinge's free rotation constrained (sampler revision 6), ddfem's
// mean vertex error was 0.65 times naive's (default sampling; 0.67 with
// revision 7, whose force patterns leave unloaded nodes free of force, and
// 0.64 with revision 8). With six
// rigid-motion constraints per face-connected group of children
// (revisions 1 to 5), no sample loaded the hinge, the coarse element took
// its stiffness across the hinge from the regularization toward the
// children's moduli, and ddfem's error was 0.94 times naive's (both
// measured with the parameters below).

#include <ddfem/solver/supports.h>

#include <filesystem>
#include <set>

#include "ddfem_against_naive.h"

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  const std::string prm  = SOURCE_DIR "/../../prm/lattice.prm",
                    file = SOURCE_DIR "/../../data/lattice.txt";
  dealii::ParameterHandler parameters;
  ddfem::app::declare_parameters(parameters);
  parameters.parse_input(prm, "", true);
  parameters.enter_subsection("Layout");
  parameters.enter_subsection("Voxel file");
  parameters.set("File name", file);
  parameters.leave_subsection();
  parameters.leave_subsection();
  ddfem::scene::Scene scene;
  scene.parse_parameters(parameters);
  const auto &grid = scene.grid;
  const auto &n    = grid.size();

  // The 2x2x2 blocks whose solid children form more than one
  // face-connected group.
  unsigned int n_blocks = 0, n_mechanisms = 0;
  for (unsigned int K = 0; K < n[2]; K += 2)
    for (unsigned int J = 0; J < n[1]; J += 2)
      for (unsigned int I = 0; I < n[0]; I += 2)
        {
          std::array<bool, 8> filled;
          for (unsigned int c = 0; c < 8; ++c)
            filled[c] =
              grid(I + (c & 1), J + ((c >> 1) & 1), K + ((c >> 2) & 1)) != 0;
          ddfem::solver::Components groups(8);
          for (unsigned int a = 0; a < 8; ++a)
            for (unsigned int d = 0; d < 3; ++d)
              if (filled[a] && filled[a ^ (1u << d)])
                groups.join(a, a ^ (1u << d));
          std::set<std::size_t> roots;
          for (unsigned int a = 0; a < 8; ++a)
            if (filled[a])
              roots.insert(groups.find(a));
          n_blocks += !roots.empty();
          n_mechanisms += roots.size() > 1;
        }
  std::cout << "solid blocks " << n_blocks << ", mechanism blocks "
            << n_mechanisms << std::endl;

  ddfem::testing::remove_database("lattice.h5");
  std::filesystem::remove_all("lattice");
  // About 17 % above the measured 0.64; revision 5 gave 0.94.
  ddfem::testing::check_ddfem_against_naive(
    "set Run type = compare\nINCLUDE " + prm +
      "\nsubsection Layout\n  subsection Voxel file\n    set File name = " +
      file + "\n  end\nend\n" +
      "subsection Database\n  set File = lattice.h5\nend\n",
    "lattice",
    0.75);
}
