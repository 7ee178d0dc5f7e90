// Coarse models on the stiff and extreme cases of the fine solver's
// stability tests: stiffness contrast 1e6 (compressed by 25 %, where the
// fine test, contrast_1e6.prm, compresses by 15 %: at 25 % the fine model's
// soft voxels fold, tests/stability/inverted.cc, while a coarse model has
// no nodes inside a block to fold them), nu = 0.49, 50 % compression, a
// 180 degree twist, a plate one voxel thick and a frame of one-voxel beams
// in a cube 90 % void, each solved with the ddfem, naive and average
// coarse models at level 1 (the compression and the twist also with the level-1
// point offset 0.45, which softens the element in bending), the twist and a
// larger compressed cube at level 2 too, whose default point offset softens
// the element in bending (the metamaterials fitted lazily into a fresh
// database per case and level-1 offset). Every solve must converge with
// det F > 0 everywhere.

#include <filesystem>
#include <fstream>

#include "../tests.h"
#include "layered_cube.h"

namespace
{
  /// The common part: output without timings, final state only.
  const std::string output = "subsection Output\n"
                             "  set Screen timings = false\n"
                             "  set Write VTU = none\n"
                             "end\n"
                             "subsection Database\n"
                             "  subsection Sampling\n"
                             "    set Patterns = 40\n"
                             "    set Stretch directions = 40\n"
                             "  end\n"
                             "end\n";

  /// A case: its name, its parameters, the coarsening levels it is solved
  /// at, and the level-1 point offsets ("default" or a number).
  struct Case
  {
    std::string               name;
    std::string               text;
    std::vector<unsigned int> levels;
    std::vector<std::string>  offsets = {"default"};
  };

  const std::vector<Case> cases = {
    {"contrast_1e6",
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
    {"nu_049",
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
     {1}},
    {"compression_50",
     ddfem::testing::compressed_cube(4, 0.5),
     {1},
     {"default", "0.45"}},
    {"compression_50_8", ddfem::testing::compressed_cube(8, 0.5), {2}},
    {"twist_180",
     "subsection Geometry\n  set Grid size = 4, 12, 4\n"
     "  set Probe points = 0.04, 0.06, 0.04\nend\n"
     "subsection Layout\n  set Type = layers\n"
     "  subsection Layers\n    set Thickness = 0.02\n"
     "    set Materials = 1, 2\n  end\nend\n"
     "subsection Boundary conditions\n"
     "  subsection Condition 1\n    set Type = fixed\n    set Region = y-\n"
     "  end\n"
     "  subsection Condition 2\n    set Type = rotation\n    set Region = y+\n"
     "    set Axis = 0, 1, 0\n    set Angle = 180\n  end\nend\n"
     "subsection Nonlinear solver\n  set Load steps = 12\nend\n",
     {1, 2},
     {"default", "0.45"}},
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
    {"void_90", "INCLUDE " SOURCE_DIR "/void_90.prm\n", {1}}};
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  for (const auto &[name, text, levels, offsets] : cases)
    {
      std::ofstream(name + ".prm") << text << output;
      // Metamaterials are fitted for one level-1 offset.
      const auto database = [&name](const std::string &offset) {
        return name + (offset == "default" ? "" : "_" + offset) + ".h5";
      };
      for (const std::string &offset : offsets)
        ddfem::testing::remove_database(database(offset));
      for (const unsigned int level : levels)
        for (const std::string &offset : offsets)
          {
            if (level == 2 && offset != "default")
              continue;
            for (const std::string method : {"ddfem", "naive", "average"})
              {
                std::cout << "=== " << name << ", " << method << ", level "
                          << level << ", point offset " << offset << std::endl;
                std::vector<std::string> arguments = {
                  name + ".prm",
                  "--set",
                  "Method=" + method,
                  "--set",
                  "Coarsening levels=" + std::to_string(level),
                  "--set",
                  "Database/File=" + database(offset),
                  "--set",
                  "Output/Output directory=" + name + "-" + method + "-" +
                    std::to_string(level) + "-" + offset};
                if (offset != "default")
                  arguments.insert(
                    arguments.end(),
                    {"--set", "Discretization/Coarse point offset=" + offset});
                const int status =
                  ddfem::app::run(arguments, std::cout, std::cout);
                std::cout << "exit status " << status << std::endl;
              }
          }
    }
}
