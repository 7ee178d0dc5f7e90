#ifndef ddfem_tests_coarsening_ddfem_against_naive_h
#define ddfem_tests_coarsening_ddfem_against_naive_h

#include "../tests.h"

namespace ddfem::testing
{
  /**
   * Runs the comparison of @p prm_text (run_comparison() in directory
   * @p name) with ddfem and naive at level 1 (ddfem_and_naive_level_1()),
   * prints "@p label exit status S, every model converged: B", and checks
   * ddfem's level-1 mean vertex error over naive's against @p bound
   * (check_below() to two digits, its name indented by @p indent).
   */
  inline void
  check_ddfem_against_naive(const std::string &prm_text,
                            const std::string &name,
                            const double       bound,
                            const std::string &label  = "",
                            const std::string &indent = "")
  {
    const auto [status, json] =
      run_comparison(prm_text + ddfem_and_naive_level_1(), name);
    bool       converged;
    const auto error = level_errors(json, 1, converged);
    std::cout << label << "exit status " << status
              << ", every model converged: " << std::boolalpha << converged
              << std::endl;
    check_below(indent + "ddfem L1 mean vertex error / naive's",
                error.at("ddfem") / error.at("naive"),
                bound,
                2);
  }
} // namespace ddfem::testing

#endif
