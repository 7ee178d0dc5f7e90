// contrast_1e6_edits.prm solved twice: each solve after an edit starts from
// the equilibrium before it (Nonlinear solver/Start after edit = last
// state), and from rest. Both reach the same states, compared at two probe
// points per state (summary.json, full precision) to 1e-10 of the lid's
// displacement of 6 mm (the prm tests compare them only through their
// 4-digit summaries), in different numbers of Newton iterations.

#include "../tests.h"

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  std::ofstream("edits.prm")
    << "INCLUDE " SOURCE_DIR "/contrast_1e6.prm\n"
       "subsection Geometry\n"
       "  set Probe points = 0.005, 0.005, 0.035; 0.035, 0.025, 0.015\n"
       "end\n"
       "subsection Layout\n"
       "  set Edits = box 0 0 0 0.02 0.04 0.04 : 2 | "
       "box 0 0 0 0.04 0.04 0.02 : 1\n"
       "end\n"
       "subsection Output\n  set Write VTU = none\nend\n";
  // The probes' displacements of every state: the base state, then after
  // each edit.
  const auto states = [](const nlohmann::json &summary) {
    std::vector<nlohmann::json> result = {summary.at("probes")};
    for (const auto &edit : summary.at("edits"))
      result.push_back(edit.at("probes"));
    return result;
  };
  // The two runs, and the Newton iterations of their solves after the
  // edits, which show that they took different paths.
  const auto run = [](const std::string &start) {
    const nlohmann::json summary = ddfem::testing::run_successfully(
      "edits.prm",
      start == "last state" ? "last_state" : start,
      {"Nonlinear solver/Start after edit=" + start});
    std::cout << "start after edit = " << start << ": Newton iterations";
    for (const auto &edit : summary.at("edits"))
      std::cout << ' ' << edit.at("newton_iterations").get<unsigned int>();
    std::cout << std::endl;
    return summary;
  };
  const auto last = states(run("last state"));
  const auto rest = states(run("rest"));
  std::cout << "states: " << last.size() << " and " << rest.size() << std::endl;
  for (std::size_t s = 0; s < std::min(last.size(), rest.size()); ++s)
    {
      double difference = 0;
      for (std::size_t p = 0; p < last[s].size(); ++p)
        for (unsigned int d = 0; d < 3; ++d)
          difference = ddfem::testing::worst(
            difference,
            std::abs(last[s][p].at("displacement")[d].get<double>() -
                     rest[s][p].at("displacement")[d].get<double>()));
      ddfem::testing::check_below("state " + std::to_string(s) + ", " +
                                    std::to_string(last[s].size()) +
                                    " probes: largest difference / 6 mm",
                                  difference / 0.006,
                                  1e-10);
    }
}
