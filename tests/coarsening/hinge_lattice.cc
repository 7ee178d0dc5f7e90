// Level-1 ddfem on a lattice: a cantilever of 8 x 32 x 8 voxels of one
// material with holes in a pattern of 4 x 4 voxels across the bar (y-z),
// repeated along it and through its width (x). A quarter of its 2x2x2
// blocks hold two solid columns that touch only along an edge: mechanism
// blocks, in a part that is connected through its faces. Their fits depend
// on whether the sampler loads the hinge. With only the hinge's free
// rotation constrained (sampler revision 6), ddfem's mean vertex error is
// 0.65 times naive's (default sampling). With six rigid-motion constraints
// per face-connected group of children (revisions 1 to 5), no sample loaded
// the hinge, the coarse element took its stiffness across the hinge from
// the regularization toward the children's moduli, and ddfem's error was
// 0.94 times naive's (both measured with the parameters below).

#include <ddfem/solver/supports.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "../tests.h"

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  // The pattern in the y-z plane, z = 0 to 3 from the first row, y = 0 to
  // 3 along each row; X is solid. The block of rows 2 and 3, columns 0 and
  // 1 holds the voxels (y, z) = (0, 2) and (1, 3) only.
  const std::array<std::string, 4> pattern = {{"..X.", "XXX.", "X.XX", ".XX."}};
  const std::array<unsigned int, 3> n      = {{8, 32, 8}};
  const auto solid = [&](const unsigned int j, const unsigned int k) {
    return pattern[k % 4][j % 4] == 'X';
  };
  {
    std::ofstream voxels("lattice.txt");
    voxels << n[0] << ' ' << n[1] << ' ' << n[2] << '\n';
    for (unsigned int k = 0; k < n[2]; ++k)
      for (unsigned int j = 0; j < n[1]; ++j)
        for (unsigned int i = 0; i < n[0]; ++i)
          voxels << (solid(j, k) ? 2 : 0) << (i + 1 < n[0] ? ' ' : '\n');
  }

  // The 2x2x2 blocks whose solid children form more than one
  // face-connected group.
  unsigned int n_blocks = 0, n_mechanisms = 0;
  for (unsigned int K = 0; K < n[2]; K += 2)
    for (unsigned int J = 0; J < n[1]; J += 2)
      for (unsigned int I = 0; I < n[0]; I += 2)
        {
          std::array<bool, 8> filled;
          for (unsigned int c = 0; c < 8; ++c)
            filled[c] = solid(J + ((c >> 1) & 1), K + ((c >> 2) & 1));
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

  for (const char *file : {"lattice.h5", "lattice.h5.journal"})
    std::filesystem::remove(file);
  std::filesystem::remove_all("lattice");
  const auto [status, json] = ddfem::testing::run_comparison(
    ddfem::testing::compare_run(
      "lattice", "8, 32, 8", "0.04, 0.315, 0.025", "0.01", "0; 0; -1000") +
      "subsection Materials\n"
      "  set Palette = E=1e5 nu=0.45; E=1e6 nu=0.45; E=1e7 nu=0.45\n"
      "end\n"
      "subsection Layout\n"
      "  set Type = voxel file\n"
      "  subsection Voxel file\n"
      "    set File name = lattice.txt\n"
      "  end\n"
      "end\n"
      "subsection Nonlinear solver\n"
      "  set Load steps = 10\n"
      "end\n" +
      ddfem::testing::ddfem_and_naive_level_1() +
      "subsection Database\n"
      "  set File = lattice.h5\n"
      "end\n",
    "lattice");
  bool       converged;
  const auto error = ddfem::testing::level_errors(json, 1, converged);
  std::cout << "exit status " << status
            << ", every model converged: " << std::boolalpha << converged
            << std::endl;
  // About 15 % above the measured 0.65; revision 5 gave 0.94.
  ddfem::testing::check_below("ddfem L1 mean vertex error / naive's",
                              error.at("ddfem") / error.at("naive"),
                              0.75);
}
