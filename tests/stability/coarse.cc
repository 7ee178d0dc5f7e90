// Coarse models on the stiff and extreme cases of the fine solver's
// stability tests: stiffness contrast 1e6, nu = 0.49, 50 % compression and
// a 180 degree twist, each solved with the ddfem and the naive coarse
// model at level 1 (the metamaterials fitted lazily into a fresh database
// per palette). Every solve must converge with det F > 0 everywhere.

#include <filesystem>
#include <fstream>

#include "../tests.h"

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

  const std::vector<std::pair<std::string, std::string>> cases = {
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
     "subsection Nonlinear solver\n  set Load steps = 5\nend\n"},
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
     "subsection Nonlinear solver\n  set Load steps = 5\nend\n"},
    {"compression_50",
     "subsection Geometry\n  set Grid size = 4, 4, 4\nend\n"
     "subsection Layout\n  set Type = layers\n"
     "  subsection Layers\n    set Axis = z\n    set Thickness = 0.01\n"
     "    set Materials = 1, 3\n  end\nend\n"
     "subsection Boundary conditions\n"
     "  subsection Condition 1\n    set Type = fixed\n    set Region = z-\n"
     "  end\n"
     "  subsection Condition 2\n    set Type = displacement\n"
     "    set Region = z+\n    set Value = 0; 0; -0.02\n  end\nend\n"
     "subsection Nonlinear solver\n  set Load steps = 10\nend\n"},
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
     "subsection Nonlinear solver\n  set Load steps = 12\nend\n"}};
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  for (const auto &[name, text] : cases)
    {
      const std::string database = name + ".h5";
      for (const std::string suffix : {"", ".journal", ".level2"})
        std::filesystem::remove(database + suffix);
      std::ofstream(name + ".prm") << text << output;
      for (const std::string method : {"ddfem", "naive"})
        {
          std::cout << "=== " << name << ", " << method << std::endl;
          const int status =
            ddfem::app::run({name + ".prm",
                             "--set",
                             "Method=" + method,
                             "--set",
                             "Database/File=" + database,
                             "--set",
                             "Output/Output directory=" + name + "-" + method},
                            std::cout,
                            std::cout);
          std::cout << "exit status " << status << std::endl;
        }
    }
}
