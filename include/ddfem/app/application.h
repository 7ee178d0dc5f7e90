#ifndef ddfem_app_application_h
#define ddfem_app_application_h

#include <deal.II/base/parameter_handler.h>

#include <ostream>
#include <string>
#include <vector>

namespace ddfem::app
{
  using namespace dealii;

  /**
   * Declares every parameter of ddfem: the scene, the discretization, the
   * solvers and the output.
   */
  void
  declare_parameters(ParameterHandler &prm);

  /**
   * The ddfem command line: `ddfem PRM [--set "Section/Name=value"]...`,
   * `ddfem --help`, `ddfem --print-parameters`. @p arguments excludes the
   * program name. Screen output goes to @p out, error messages to @p err.
   * Returns the process exit code: 0 on success, 1 on bad input or a solve
   * that did not converge, or when started as more than one MPI process.
   * All input is validated before anything is written to the output
   * directory.
   */
  int
  run(const std::vector<std::string> &arguments,
      std::ostream                   &out,
      std::ostream                   &err);
} // namespace ddfem::app

#endif
