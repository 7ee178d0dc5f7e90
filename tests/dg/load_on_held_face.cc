// A load on a face whose displacement a condition prescribes goes into the
// reactions. A load on held components only is an input error (it would do
// nothing; tests/ddfem/bad_input.cc), so the loads here reach held and free
// faces, and the runs compare them with the same load on the free faces
// alone. The default cantilever (clamped on y-, traction on y+) under a
// traction of 200 Pa on every face gives the same probes as under that
// traction on every face but the clamped one, for DG with weak (Nitsche)
// and strong conditions and for CG. Weak conditions added the load on the
// clamped face to the Nitsche terms before (2000 Pa on it alone moved the
// clamped face's centre by 0.078 mm and the tip by 0.098 mm).
// A sliding face (x-, only u_x held) under a pressure, which pushes on the
// held component only, changes nothing either.

#include <ddfem/app/application.h>

#include <fstream>
#include <iomanip>

#include "../tests.h"
#include "probes.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  /// The probes' displacements of a run of prm/default.prm with the
  /// settings @p extra (testing::run_model()), written to @p directory.
  std::vector<Tensor<1, 3>>
  probes(const std::string &directory, const std::vector<std::string> &extra)
  {
    std::vector<std::string> settings = {
      "Output/Write VTU=none",
      "Geometry/Probe points=0.04, 0.32, 0.04; 0.04, 0, 0.04; 0, 0.16, 0.04"};
    settings.insert(settings.end(), extra.begin(), extra.end());
    return testing::probe_displacements(testing::run_successfully(
      std::string(SOURCE_DIR) + "/../../prm/default.prm", directory, settings));
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  // The traction on every face, and on every face but the clamped y- ones
  // (whose centers lie at y = 0).
  const auto traction = [](const std::string &region) {
    return std::vector<std::string>{
      "Boundary conditions/Condition 3/Type=traction",
      "Boundary conditions/Condition 3/Region=" + region,
      "Boundary conditions/Condition 3/Value=0; 0; -200"};
  };
  const auto on_all  = traction("box 0 0 0 0.08 0.32 0.08");
  const auto on_free = traction("box 0 0.001 0 0.08 0.32 0.08");
  for (const auto &[name, settings] :
       {std::make_pair("CG", std::vector<std::string>{"Method=fine"}),
        std::make_pair("DG, weak conditions",
                       std::vector<std::string>{"Method=dg"}),
        std::make_pair("DG, strong conditions",
                       std::vector<std::string>{"Method=dg",
                                                "DG/Dirichlet=strong"})})
    {
      std::vector<std::string> loaded = settings, loaded_free = settings;
      loaded.insert(loaded.end(), on_all.begin(), on_all.end());
      loaded_free.insert(loaded_free.end(), on_free.begin(), on_free.end());
      const auto without = probes("without", loaded_free);
      const auto with    = probes("with", loaded);
      std::cout << name << ": tip u_z = " << std::setprecision(4)
                << 1e3 * without[0][2]
                << " mm; the traction on the clamped face too" << std::endl;
      testing::check_below("  moves the tip by (relative)",
                           (with[0] - without[0]).norm() / without[0].norm(),
                           1e-9);
      testing::check_below("  moves the clamped face's centre by (relative)",
                           (with[1] - without[1]).norm() / without[0].norm(),
                           1e-9);
    }

  // A sliding face under a pressure, with weak conditions: a pressure on
  // the upper half of the bar, x- face included, moves the tip and the
  // probe on x- as much as without the x- face.
  const auto pressure = [](const std::string &name, const std::string &region) {
    return probes(name,
                  {"Method=dg",
                   "Boundary conditions/Condition 3/Type=sliding",
                   "Boundary conditions/Condition 3/Region=x-",
                   "Boundary conditions/Condition 4/Type=pressure",
                   "Boundary conditions/Condition 4/Region=" + region,
                   "Boundary conditions/Condition 4/Value=1e3"});
  };
  const auto sliding = pressure("sliding", "box 0 0.16 0 0.08 0.32 0.08");
  const auto reference =
    pressure("sliding_free_faces", "box 0.001 0.16 0 0.08 0.32 0.08");
  std::cout << "DG, weak conditions, sliding x- face under a pressure"
            << std::endl;
  testing::check_below("  changes the probes by (relative)",
                       (sliding[0] - reference[0]).norm() /
                           reference[0].norm() +
                         (sliding[2] - reference[2]).norm() /
                           reference[0].norm(),
                       1e-9);
}
