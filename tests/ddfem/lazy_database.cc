// Run type = database with Database/Scope = scene fits the blocks of every
// state of the scene, its material edits included, so that a simulation
// of the scene afterwards finds every entry it needs and fits nothing (and
// writes its coarsening time into summary.json).

#include <ddfem/app/application.h>
#include <ddfem/coarsening/database.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "../tests.h"

namespace
{
  /// Runs @p run_type on a 2x4x2-voxel cantilever of material 1 whose one
  /// edit paints voxel (0, 2, 0) with material 2: its base state has one
  /// kind of 2x2x2 block, the edited state a second one. Prints the exit
  /// status, the database report's "to fit" line and the entries in the
  /// file afterwards.
  void
  run(const std::string &name, const std::string &run_type)
  {
    std::ofstream(name + ".prm")
      << "set Run type = " << run_type << "\n"
      << ddfem::testing::cantilever("2, 4, 2", "0; 0; -1000")
      << "set Method = ddfem\n"
         "subsection Geometry\n"
         "  set Voxel size = 1\n"
         "end\n"
         "subsection Layout\n"
         "  set Material = 1\n"
         "  set Edits = box 0 2 0 1 3 1 : 2\n"
         "end\n"
      << ddfem::testing::cheap_lazy_database("db.h5")
      << ddfem::testing::quiet_output(name);
    std::ostringstream log;
    const int          status = ddfem::app::run({name + ".prm"}, log, log);
    std::cout << run_type << ": exit status " << status << std::endl;
    std::istringstream lines(log.str());
    for (std::string line; std::getline(lines, line);)
      if (line.find("to fit") != std::string::npos)
        std::cout << "  " << line << std::endl;
    std::cout << "  entries in db.h5: "
              << ddfem::coarsening::Database::load("db.h5").entries().size()
              << std::endl;
    // A coarse simulation's summary.json has the coarsening (lookup) time:
    // measured, so above 0, and part of the wall time.
    if (run_type == "simulation")
      {
        std::ifstream        file(name + "/summary.json");
        const nlohmann::json summary = nlohmann::json::parse(file);
        const auto          &time    = summary.at("coarsening_time_s");
        std::cout << "  summary.json: coarsening_time_s is "
                  << (time.is_number() && time.get<double>() > 0 &&
                          time.get<double>() <
                            summary.at("wall_time_s").get<double>() ?
                        "above 0 and below the wall time" :
                        "not a number above 0 and below the wall time")
                  << std::endl;
      }
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  ddfem::testing::remove_database("db.h5");
  run("database", "database");
  run("simulation", "simulation");
}
