// Level-1 ddfem on a cantilever of layers one voxel thick (prm/default.prm
// with Layout/Layers/Thickness = 0.02), so that every 2x2x2 block is split
// in two layers of different materials, with 'Database/Fitting/Laminate
// springs = true' (laminate_springs()). With the springs the blocks'
// mirror symmetries keep (the default), ddfem's mean vertex error is 18
// (layers normal to x) and 21 (normal to z) times naive's, because bending
// stretches the layers in their plane and the fit can only make the block
// soft. Here: with the layers along the bar (normal to x or z), ddfem's
// error is below 4.2 and 0.8 times naive's, respectively; across the bar
// (normal to y), where naive is far too stiff, below 0.36 times naive's
// (the bounds are below). The same part is run again with the palette in the
// reverse order: the springs follow the materials, not their ids (with the
// plane's axes on the half below the plane of each orbit's representative, the
// layers normal to z gave 9.7 times naive's error there).

#include <filesystem>
#include <map>

#include "ddfem_against_naive.h"

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  // The largest ratio ddfem / naive each layer normal may have: about 15 %
  // above the measured 3.6, 0.30 and 0.69 (either palette order); without
  // laminate springs x and z reach 18 and 21, and springs that followed
  // the palette's order instead of the materials gave z 9.7 with the
  // palette reversed.
  const std::array<std::pair<std::string, double>, 3> bounds = {
    {{"x", 4.2}, {"y", 0.36}, {"z", 0.8}}};
  // The palette soft to stiff, and stiff to soft with the ids of the
  // layers reversed: the same part.
  const std::array<std::array<std::string, 4>, 2> palettes = {
    {{"", "E=1e5 nu=0.45; E=1e6 nu=0.45; E=1e7 nu=0.45", "1, 2, 3", "layers"},
     {", palette reversed",
      "E=1e7 nu=0.45; E=1e6 nu=0.45; E=1e5 nu=0.45",
      "3, 2, 1",
      "reversed"}}};
  for (const char *file : {"layers.h5", "reversed.h5"})
    ddfem::testing::remove_database(file);
  for (const auto &[label, palette, ids, database] : palettes)
    for (const auto &[axis, bound] : bounds)
      {
        const std::string directory = "layers-" + axis;
        std::filesystem::remove_all(directory);
        ddfem::testing::check_ddfem_against_naive(
          ddfem::testing::compare_run("layers",
                                      "4, 16, 4",
                                      "0.04, 0.32, 0.04") +
            ddfem::testing::layers("0.02", axis, palette, ids) +
            "subsection Database\n"
            "  set File = " +
            database +
            ".h5\n"
            "  subsection Fitting\n"
            "    set Laminate springs = true\n"
            "  end\n"
            "end\n",
          directory,
          bound,
          "layers normal to " + axis + label + ": ",
          "  ");
      }
}
