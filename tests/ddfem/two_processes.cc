// ddfem started as two MPI processes refuses to run: both would run the
// whole job and write the same output and database files. Only the first
// process reports the error; both return exit code 1 and write nothing.

#include <deal.II/base/mpi.h>

#include <ddfem/app/application.h>

#include <filesystem>
#include <sstream>

#include "../tests.h"

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const unsigned int                       rank =
    dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD);

  // What an earlier run of the test left must not count as written.
  if (rank == 0)
    std::filesystem::remove_all("written");
  MPI_Barrier(MPI_COMM_WORLD);
  std::ostringstream out, err;
  const int          code = ddfem::app::run({SOURCE_DIR "/../../prm/bar.prm",
                                             "--set",
                                             "Output/Output directory=written"},
                                   out,
                                   err);
  const unsigned int refused =
    dealii::Utilities::MPI::sum(code == 1 ? 1u : 0u, MPI_COMM_WORLD);
  const unsigned int reported =
    dealii::Utilities::MPI::sum(err.str().empty() ? 0u : 1u, MPI_COMM_WORLD);
  const unsigned int written = dealii::Utilities::MPI::sum(
    !out.str().empty() || std::filesystem::exists("written") ? 1u : 0u,
    MPI_COMM_WORLD);
  // --help is refused too (each process printed the usage).
  std::ostringstream help_out, help_err;
  const unsigned int help_refused = dealii::Utilities::MPI::sum(
    ddfem::app::run({"--help"}, help_out, help_err) == 1 &&
        help_out.str().empty() ?
      1u :
      0u,
    MPI_COMM_WORLD);
  if (rank == 0)
    std::cout << "processes that refused --help: " << help_refused << std::endl
              << "processes that returned 1: " << refused << std::endl
              << "processes that reported an error: " << reported << std::endl
              << "processes that wrote output: " << written << std::endl
              << err.str();
}
