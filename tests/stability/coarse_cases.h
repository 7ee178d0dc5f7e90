#ifndef ddfem_tests_stability_coarse_cases_h
#define ddfem_tests_stability_coarse_cases_h

#include <iostream>
#include <string>
#include <vector>

#include "../tests.h"

// The driver of the coarse models' stiff and extreme cases. They are split
// over coarse_contrast.cc, coarse_incompressible.cc, coarse_compression.cc
// and coarse_twist.cc, so that each test stays well inside ctest's time
// limit in a Debug build, where the lazy fits take minutes. A solve that
// does not converge, or ends with det F <= 0 at a quadrature point or a
// vertex, prints its error and a nonzero exit status.

namespace ddfem::testing
{
  /**
   * A stiff or extreme case for the coarse models: its name, its parameter
   * text, the coarsening levels it is solved at, and the level-1 point
   * offsets ("default" or a number).
   */
  struct CoarseCase
  {
    std::string               name;
    std::string               text;
    std::vector<unsigned int> levels;
    std::vector<std::string>  offsets = {"default"};
  };

  /**
   * Solve every case with the ddfem, naive and average coarse models at each
   * of its levels and level-1 point offsets (level 2 at the default offset
   * only), each printing its final state without timings and its exit
   * status. The metamaterials are fitted lazily, with 40 force patterns and
   * 40 stretch directions, into a fresh database per case and level-1
   * offset.
   */
  inline void
  solve_coarse_cases(const std::vector<CoarseCase> &cases)
  {
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
    for (const auto &[name, text, levels, offsets] : cases)
      {
        std::ofstream(name + ".prm") << text << output;
        const auto database = [&name](const std::string &offset) {
          return name + (offset == "default" ? "" : "_" + offset) + ".h5";
        };
        for (const std::string &offset : offsets)
          remove_database(database(offset));
        for (const unsigned int level : levels)
          for (const std::string &offset : offsets)
            {
              if (level == 2 && offset != "default")
                continue;
              for (const std::string method : {"ddfem", "naive", "average"})
                {
                  std::cout << "=== " << name << ", " << method << ", level "
                            << level << ", point offset " << offset
                            << std::endl;
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
                    arguments.insert(arguments.end(),
                                     {"--set",
                                      "Discretization/Coarse point offset=" +
                                        offset});
                  const int status =
                    ddfem::app::run(arguments, std::cout, std::cout);
                  std::cout << "exit status " << status << std::endl;
                }
            }
      }
  }
} // namespace ddfem::testing

#endif
