#include <deal.II/base/mpi.h>

#include <ddfem/app/application.h>
#include <dlfcn.h>

#include <iostream>

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv);
  // UMFPACK's dense kernels call BLAS. Debian's OpenBLAS (pthread flavour)
  // starts its own threads, which busy-wait between calls and compete with
  // the TBB threads of the assembly: on 2 cores a comparison run measured
  // the fine direct solve 3.2 times slower with them than with one BLAS
  // thread (doc/coarsening.md). Other BLAS libraries lack the symbol and
  // are left alone.
  using SetThreads = void (*)(int);
  if (const auto set_threads = reinterpret_cast<SetThreads>(
        dlsym(RTLD_DEFAULT, "openblas_set_num_threads")))
    set_threads(1);
  return ddfem::app::run(std::vector<std::string>(argv + 1, argv + argc),
                         std::cout,
                         std::cerr);
}
