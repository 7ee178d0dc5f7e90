// The shipped parameter files that no other test reads: the database
// build and the two DG studies (tests/scenes runs the scene files). Each is
// read by the classes its run type uses, so that a parameter renamed or
// removed, or a value out of its range, fails here rather than in the
// README's commands. Nothing is built or solved.

#include <ddfem/app/application.h>
#include <ddfem/coarsening/builder.h>
#include <ddfem/dg/studies.h>
#include <ddfem/scene/scene.h>

#include "../tests.h"

using namespace ddfem;
using namespace dealii;

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  for (const std::string name :
       {"database", "dg_poisson_convergence", "dg_elasticity_cost"})
    {
      ParameterHandler prm;
      app::declare_parameters(prm);
      prm.parse_input(std::string(SOURCE_DIR) + "/../../prm/" + name + ".prm");
      const std::string run_type = prm.get("Run type");
      std::cout << "prm/" << name << ".prm: Run type = " << run_type;
      if (run_type == "database")
        {
          scene::Scene scene;
          scene.parse_parameters(prm);
          coarsening::DatabaseBuilder builder;
          builder.parse_parameters(prm);
          prm.enter_subsection("Database");
          const unsigned int levels = prm.get_integer("Levels");
          prm.leave_subsection();
          builder.check_input(scene.palette, levels);
          std::cout << ", " << scene.palette.size() << " materials";
        }
      else if (run_type == "dg convergence")
        {
          dg::ConvergenceStudy study;
          study.parse_parameters(prm);
        }
      else
        {
          dg::CostStudy study;
          study.parse_parameters(prm);
        }
      std::cout << ": read" << std::endl;
    }
}
