// The scene's 'Linear solver' for DG (doc/dg.md, "Solver"): DG systems
// solved directly ('direct', what 'auto' takes up to 'Direct solver limit'
// unknowns: sparse Cholesky, UMFPACK where the matrix is not positive
// definite), CG with a Cholesky factor and CG with algebraic multigrid,
// each to a relative residual of 1e-12:
// - the default scene (linear, FE_DGQ(1), 6144 DoFs, so the multigrid has
//   more than one level; its automatic penalty 4 given as a fixed one and
//   left unchecked, since a linear system whose check passed is solved with
//   the check's Cholesky factor): the probe agrees within 1e-9 of its
//   length, and so does the check's factor at the automatic penalty; 'auto'
//   with 'Direct solver limit = 0' runs cg-amg;
// - corotated_twist.prm (corotated, 6 load steps): the probe agrees within
//   1e-9, and the iterative solvers need as many fixed-point solves;
// - where multigrid fails (nu_0499.prm: FE_DGQ(2) at nu = 0.499, 500 CG
//   iterations do not reach 1e-12) the run stops with a message that
//   names the solver and suggests the direct one, once, also for the
//   corotated formulation; a corotated iteration that runs out of
//   iterations with iterative solves suggests it too;
// - a fixed penalty too small for a positive definite matrix (2 on the
//   default scene) goes to UMFPACK;
// - FE_DGP has no support points for the multigrid's rigid body modes:
//   cg-amg for its corotated iterations is an error that names Linear
//   solver/Type.

#include <ddfem/app/application.h>

#include "../tests.h"
#include "probes.h"

using namespace ddfem;

namespace
{
  /// What the summary calls the direct solver of corotated iterations and
  /// unchecked linear systems.
  const std::string direct_solver =
    "cholesky (UMFPACK where not positive definite)";

  /// The probes of a run of @p prm (a path from this directory) with
  /// @p type and @p settings, and its summary's "linear_solves" and
  /// "linear_iterations"; the exit status must be 0, and the summary's
  /// "linear_solver" @p solver (by default @p type, for 'direct'
  /// direct_solver).
  std::tuple<std::vector<dealii::Tensor<1, 3>>, unsigned int, unsigned int>
  run(const std::string              &prm,
      const std::string              &type,
      const std::vector<std::string> &settings,
      const std::string              &solver = "")
  {
    std::vector<std::string> all = settings;
    all.push_back("Linear solver/Type=" + type);
    std::ostringstream screen;
    const auto [status, summary] = testing::run_model(
      std::string(SOURCE_DIR) + "/" + prm, "run-" + type, all, screen);
    AssertThrow(status == 0, dealii::ExcMessage(screen.str()));
    AssertThrow(summary.at("linear_solver") ==
                  (!solver.empty()  ? solver :
                   type == "direct" ? direct_solver :
                                      type),
                dealii::ExcMessage("another solver ran"));
    return {testing::probe_displacements(summary),
            summary.at("linear_solves"),
            summary.at("linear_iterations")};
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  // A linear system whose definiteness check passed is solved with the
  // check's factor, so the default scene takes its automatic penalty (4)
  // as a fixed one, unchecked, for the scene's solvers.
  const std::vector<std::string> scene     = {"Method=dg",
                                              "Output/Write VTU=none",
                                              "Output/Screen timings=false"};
  std::vector<std::string>       unchecked = scene;
  unchecked.insert(unchecked.end(),
                   {"DG/Penalty=4", "DG/Definiteness check limit=0"});
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
    {"../../prm/default.prm", unchecked}, {"corotated_twist.prm", {}}};
  for (const auto &[prm, settings] : cases)
    {
      const auto [direct, direct_solves, unused] = run(prm, "direct", settings);
      std::cout << prm << ": direct, linear solves " << direct_solves
                << std::endl;
      AssertThrow(!direct.empty(), dealii::ExcMessage("no probes"));
      std::vector<
        std::tuple<std::string, std::vector<std::string>, std::string>>
        runs = {{"cg-cholesky", settings, ""}, {"cg-amg", settings, ""}};
      if (direct_solves == 1)
        {
          runs.emplace_back("auto", settings, "cg-amg");
          std::get<1>(runs.back())
            .push_back("Linear solver/Direct solver limit=0");
          runs.emplace_back("direct", scene, "cholesky of the penalty check");
        }
      for (const auto &[type, run_settings, solver] : runs)
        {
          const auto [probes, solves, iterations] =
            run(prm, type, run_settings, solver);
          AssertThrow(probes.size() == direct.size(),
                      dealii::ExcMessage("probes missing"));
          double difference = 0;
          for (unsigned int p = 0; p < probes.size(); ++p)
            difference =
              testing::worst(difference,
                             (probes[p] - direct[p]).norm() / direct[p].norm());
          const std::string name = type == "direct" ? solver : type;
          std::cout << "  " << name << ": linear solves " << solves
                    << ", iterations " << iterations << std::endl;
          testing::check_below(
            "  " + name + ": |u - u(direct)| / |u(direct)| at the probes",
            difference,
            1e-9); // round-off and solver tolerances: not pinned
        }
    }

  // A penalty too small for a positive definite matrix: the Cholesky
  // factorization fails and UMFPACK solves.
  {
    std::vector<std::string> settings = scene;
    settings.insert(settings.end(),
                    {"DG/Penalty=2", "DG/Definiteness check limit=0"});
    std::ostringstream screen;
    const auto [status, summary] =
      testing::run_model(std::string(SOURCE_DIR) + "/../../prm/default.prm",
                         "run-indefinite",
                         settings,
                         screen);
    AssertThrow(status == 0, dealii::ExcMessage(screen.str()));
    std::cout << "default scene, DG/Penalty = 2: "
              << summary.at("linear_solver").get<std::string>()
              << ", linear solves " << summary.at("linear_solves")
              << ", of which with a Cholesky factor "
              << summary.at("cholesky_solves") << std::endl;
  }

  // Runs that must fail with a message naming the solver (and, where CG
  // fails, suggesting the direct one). The scene's solver serves the
  // corotated iterations and unchecked linear systems only.
  const std::vector<std::string> cg_fails = {
    "Linear solver/Type = cg-amg: CG did not converge", "try Type = direct"};
  for (const auto &[prm, settings, expected] :
       {std::make_tuple(
          "nu_0499.prm",
          std::vector<std::string>{"DG/Penalty=16",
                                   "DG/Definiteness check limit=0",
                                   "Linear solver/Type=cg-amg"},
          cg_fails),
        std::make_tuple("nu_0499.prm",
                        std::vector<std::string>{"DG/Formulation=corotated",
                                                 "Linear solver/Type=cg-amg"},
                        cg_fails),
        std::make_tuple(
          "corotated_twist.prm",
          std::vector<std::string>{"DG/Corotation iterations=2",
                                   "Linear solver/Type=cg-cholesky"},
          std::vector<std::string>{
            "did not converge in DG/Corotation iterations = 2",
            "The linear solves were iterative",
            "try Type = direct"}),
        std::make_tuple("contrast_1e6.prm",
                        std::vector<std::string>{"DG/Element=FE_DGP",
                                                 "DG/Formulation=corotated",
                                                 "Linear solver/Type=cg-amg"},
                        std::vector<std::string>{
                          "Linear solver/Type = cg-amg (or auto"})})
    {
      std::ostringstream screen;
      const int status = testing::run_model(std::string(SOURCE_DIR) + "/" + prm,
                                            "failing",
                                            settings,
                                            screen)
                           .first;
      // Each expected text appears exactly once.
      bool found = true;
      for (const std::string &text : expected)
        {
          const std::size_t first = screen.str().find(text);
          found                   = found && first != std::string::npos &&
                  screen.str().find(text, first + 1) == std::string::npos;
        }
      std::cout << prm << " with";
      for (const std::string &setting : settings)
        std::cout << " " << setting;
      std::cout << ": exit status " << status
                << ", the message as expected: " << std::boolalpha << found
                << std::endl;
    }
}
