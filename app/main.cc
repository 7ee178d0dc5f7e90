#include <deal.II/base/mpi.h>

#include <ddfem/app/application.h>

#include <iostream>

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv);
  return ddfem::app::run(std::vector<std::string>(argv + 1, argv + argc),
                         std::cout,
                         std::cerr);
}
