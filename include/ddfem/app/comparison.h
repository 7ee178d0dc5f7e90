#ifndef ddfem_app_comparison_h
#define ddfem_app_comparison_h

#include <deal.II/base/parameter_handler.h>

#include <ddfem/coarsening/builder.h>
#include <ddfem/report/output.h>
#include <ddfem/scene/scene.h>
#include <ddfem/solver/linear_solver.h>
#include <ddfem/solver/static_solver.h>

#include <filesystem>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace ddfem::app
{
  using namespace dealii;

  class ModelRun;

  /**
   * Throws ExcMessage naming Output/Output directory before anything is
   * solved if remove_earlier_results() could not remove what it removes
   * from @p directory (VTU files of the directory itself aside, which each
   * run type checks with its own states), or if a directory where a compare
   * run keeps a model's VTU files holds another run's parameters.prm (it is
   * that run's output directory), or if @p directory is such a directory
   * of a compare run (its parent holds comparison.json); and naming
   * Database/File if
   * @p database_file (empty: the run uses no database) is a result file
   * that a run writes there or removes as an earlier run's, which would
   * overwrite or delete the database, or is the output directory or a
   * directory it lies in.
   */
  void
  check_earlier_results(const std::string       &directory,
                        const report::VtuWriter &vtu,
                        const std::string       &database_file);

  /**
   * Removes what an earlier simulation, comparison or DG study left in the
   * output directory @p directory, so that none of it is taken for this
   * run's: summary.json, the comparison's tables and plot, the studies'
   * tables and figures, and every VTU file there and in the directory of
   * every model a comparison can have.
   */
  void
  remove_earlier_results(const std::string &directory);

  /**
   * Cleans up after a run that failed while writing its results to
   * @p directory: removes them (remove_earlier_results(), which leaves
   * parameters.prm to the caller), then those of the directories @p made
   * for them (as create_directories() returned them) that are left empty.
   * Best effort, it throws nothing: the error to report is the run's.
   */
  void
  remove_failed_results(const std::string                        &directory,
                        const std::vector<std::filesystem::path> &made);

  /**
   * Run type "compare": error against run time (DDFEM paper, section 6).
   * Solves one scene in one process with the fine model (with the scene's
   * linear solver, with cg-amg if that is another one, and, up to a size
   * limit, with UMFPACK at every Newton iteration) and with every
   * coarse method at every coarsening level asked for; measures each
   * coarse solution's vertex error against the fine one, the least error
   * any field on each coarse grid can have (report::grid_fit(): what the
   * grid costs whatever the materials), and every run's wall time; writes
   * comparison.csv, comparison.json, error_vs_time.png (gnuplot) and VTU files
   * of every solution, and prints the table. With material edits in the scene,
   * every state (before the first edit and after each) is compared, the models
   * re-coarsening only the changed blocks. Declared in the prm subsection
   * "Comparison".
   */
  class Comparison
  {
  public:
    /// Declares the subsection "Comparison".
    static void
    declare_parameters(ParameterHandler &prm);

    /// Reads "Comparison" and everything the runs need from @p prm.
    void
    parse_parameters(ParameterHandler &prm);

    /**
     * Runs the comparison of @p scene (named @p scene_name) and writes its
     * results to @p directory, with @p prm (the parameters of the run) as
     * parameters.prm next to its tables. Logs to @p out; timings on screen
     * only if @p screen_timings (files always have them). Returns 0 if every
     * solve converged, 1 otherwise. A run that stops with an error in its
     * checks, before anything is solved, leaves the directory as it was; one
     * that stops later, before its tables are written, leaves no result of
     * its own nor an earlier run's, parameters.prm included, unless that
     * file is one of @p inputs (the parameter file and the files it
     * includes, resolved_path()): a rerun from it keeps it. The plot is of
     * the first state; without a coarse model with an error there it is not
     * drawn, which the log says.
     */
    int
    run(const ParameterHandler         &prm,
        scene::Scene                   &scene,
        const std::string              &scene_name,
        const std::string              &directory,
        const std::vector<std::string> &inputs,
        const bool                      screen_timings,
        std::ostream                   &out);

  private:
    /**
     * The part of run() that writes results: solves every state of
     * @p scene with the @p models set up for the configurations (null:
     * skipped), measures, writes the tables and parameters.prm (then sets
     * @p tables_written) and draws the plot. Returns as run() does.
     */
    int
    solve_and_write(const ParameterHandler                 &prm,
                    scene::Scene                           &scene,
                    const std::string                      &scene_name,
                    const std::string                      &directory,
                    std::vector<std::unique_ptr<ModelRun>> &models,
                    bool                                    screen_timings,
                    std::ostream                           &out,
                    bool                                   &tables_written);

    /// One model compared: the fine one (with a given linear solver) or a
    /// coarse method at a level.
    struct Configuration
    {
      /// "fine", "fine-amg", "fine-direct", "ddfem", "naive" or "average".
      std::string name;
      /// Coarsening level (0 for fine).
      unsigned int level = 0;
      /// Its linear solver.
      std::unique_ptr<solver::LinearSolver> linear_solver;
    };
    std::vector<Configuration> configurations;
    /// Largest fine system also solved with the direct solver.
    unsigned int direct_limit = 0;
    /// Degree of the fine model.
    unsigned int degree = 1;

    solver::StaticSolver::Parameters solver_parameters;
    report::VtuWriter                vtu;
    coarsening::DatabaseBuilder      database;
    /// The directories run() made for its results, parents first: a run
    /// that fails before its tables are written removes them again.
    std::vector<std::filesystem::path> made_directories;
  };
} // namespace ddfem::app

#endif
