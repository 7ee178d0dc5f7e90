// The coarse models do not depend on units. Every Young's modulus and the
// load times 10, or every length times 2 under the same traction, leave
// the strains, and so the fits and every relative vertex error, as they
// were: the sampler scales its patterns to strains, the fit measures its
// residuals and parameters relative to the block's energies and moduli,
// and the vertex error divides by the part's size. A compare run of the
// default scene (prm/default.prm without its VTU files) with ddfem and
// naive at levels 1 and 2, each with a database of its own, is run three
// times; the mean and max vertex errors of every coarse model must agree
// to 1e-8.

#include <filesystem>
#include <map>

#include "../tests.h"

namespace
{
  /// The default scene with the given palette, tip traction and voxel size.
  std::string
  scene(const std::string &palette,
        const std::string &traction,
        const double       voxel,
        const std::string &database)
  {
    const auto length = [&](const double voxels) {
      return std::to_string(voxels * voxel);
    };
    return ddfem::testing::compare_run("units",
                                       "4, 16, 4",
                                       length(2) + ", " + length(16) + ", " +
                                         length(2),
                                       length(1),
                                       traction) +
           ddfem::testing::layers(length(2), "y", palette) +
           "subsection Comparison\n"
           "  set Methods = ddfem, naive\n"
           "  set Levels = 1, 2\n"
           "  set Fine direct solver limit = 0\n"
           "end\n"
           "subsection Database\n"
           "  set File = " +
           database + "\nend\n";
  }

  /// Mean and max vertex errors of every coarse model, by method and level.
  std::map<std::pair<std::string, int>, std::array<double, 2>>
  errors(const std::string &prm_text, const std::string &name)
  {
    std::filesystem::remove_all(name);
    ddfem::testing::remove_database(name + ".h5");
    const auto [status, json] = ddfem::testing::run_comparison(prm_text, name);
    std::map<std::pair<std::string, int>, std::array<double, 2>> result;
    bool converged = true;
    for (const auto &run : json.at("runs"))
      {
        converged &= run.at("converged").get<bool>();
        if (run.at("level") != 0)
          result[{run.at("method"), run.at("level")}] = {
            {run.at("mean_vertex_error"), run.at("max_vertex_error")}};
      }
    std::cout << name << ": exit status " << status
              << ", every model converged: " << std::boolalpha << converged
              << ", coarse models: " << result.size() << std::endl;
    return result;
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  const std::string palette = "E=1e5 nu=0.45; E=1e6 nu=0.45; E=1e7 nu=0.45";
  const auto        reference =
    errors(scene(palette, "0; 0; -2000", 0.02, "reference.h5"), "reference");
  const auto stiffer = errors(scene("E=1e6 nu=0.45; E=1e7 nu=0.45; "
                                    "E=1e8 nu=0.45",
                                    "0; 0; -20000",
                                    0.02,
                                    "stiffer.h5"),
                              "stiffer");
  const auto larger =
    errors(scene(palette, "0; 0; -2000", 0.04, "larger.h5"), "larger");

  for (const auto &[label, run] :
       {std::pair{"moduli and load times 10", &stiffer},
        std::pair{"lengths times 2", &larger}})
    {
      double change = run->size() == reference.size() ? 0 : 1;
      for (const auto &[model, error] : reference)
        for (unsigned int i = 0; i < 2; ++i)
          change = ddfem::testing::worst(
            change, std::abs(run->at(model)[i] - error[i]) / error[i]);
      ddfem::testing::check_below(
        std::string(label) +
          ": relative change of every coarse model's mean and max vertex "
          "error",
        change,
        1e-8);
    }
}
