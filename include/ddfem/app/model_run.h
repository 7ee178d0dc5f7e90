#ifndef ddfem_app_model_run_h
#define ddfem_app_model_run_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/vector.h>

#include <ddfem/coarsening/coarsener.h>
#include <ddfem/report/output.h>
#include <ddfem/scene/scene.h>
#include <ddfem/solver/discretization.h>
#include <ddfem/solver/linear_solver.h>
#include <ddfem/solver/static_solver.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace ddfem::app
{
  using namespace dealii;

  /// A probe point and the displacement there (m).
  struct Probe
  {
    /// Where the displacement was evaluated.
    Point<3> point;
    /// The displacement.
    Tensor<1, 3> displacement;
  };

  /**
   * The JSON of @p probes: an array of {"point": [x, y, z], "displacement":
   * [u, v, w]}, in m, as summary.json and comparison.json write them.
   */
  nlohmann::json
  to_json(const std::vector<Probe> &probes);

  /**
   * One continuous model of a scene and its solves: the fine model
   * (level 0) or a coarse one (a Coarsener fills its material records),
   * with one Newton solver and linear solver. The model is set up once;
   * after a material edit only the touched cells get new materials
   * (re-coarsening only the changed blocks), and the solver takes them
   * (StaticSolver::update_materials()) before the next solve.
   */
  class ModelRun
  {
  public:
    /// What one solve produced.
    struct Result
    {
      /// Newton solver statistics.
      solver::StaticSolver::Statistics statistics;
      /// Whether the model is coarse (has a coarsening time).
      bool coarse = false;
      /// Wall time of coarsening (lookups) or, after edits, re-coarsening
      /// (s); 0 for the fine model. Since the last solve: summed over its
      /// coarsening and the edits that followed.
      double coarsening_time = 0;
      /// Cells given their materials for this solve: after an edit, the
      /// coarse blocks (fine cells) it changed; in the base state, every
      /// cell of a coarse model (its first coarsening) and 0 for the fine
      /// model (whose materials come with its mesh). Summed like the
      /// coarsening time, so a cell that two edits change counts twice.
      unsigned int cells_updated = 0;
      /// Wall time of setup, coarsening and solve, without output (s).
      double wall_time = 0;
      /// Wall time per timer section (s).
      std::map<std::string, double> phases;
      /// Smallest det F at any quadrature point in the final state.
      double min_J = 1;
      /// Median, 99th percentile and largest over the cells of each cell's
      /// largest principal strain (StaticSolver::CellFields::strain), by
      /// ddfem::quantile().
      std::array<double, 3> strain_quantiles = {{0, 0, 0}};
      /// Largest displacement (m): at any node of a fine model, at the
      /// solid voxels' corners for a coarse one (whose nodes may lie in
      /// void).
      double max_displacement = 0;
      /// Each probe point and the displacement there (m).
      std::vector<Probe> probes;

      /// Wall time per Newton iteration (s; the whole wall time if none).
      double
      time_per_iteration() const
      {
        return wall_time / std::max(1u, statistics.newton_iterations);
      }

      /// The result as JSON (times in seconds, lengths in meters); the
      /// fine model's coarsening time is null.
      nlohmann::json
      to_json() const;
    };

    /**
     * The model of @p scene at coarsening level @p coarsener->level(), or
     * the fine model of degree @p degree if @p coarsener is null. Builds
     * the discretization, coarsens (timed) and sets the solver up with
     * @p linear_solver. Throws ExcMessage on invalid input (e.g. probes
     * outside the solid). The arguments must outlive the object.
     */
    ModelRun(const scene::Scene                     &scene,
             const unsigned int                      degree,
             const coarsening::Coarsener            *coarsener,
             const solver::StaticSolver::Parameters &parameters,
             solver::LinearSolver                   &linear_solver,
             ConditionalOStream                     &log);

    /**
     * The scene's voxels @p changed were given new (solid) materials: the
     * cells holding them get new material records.
     */
    void
    edit(const std::vector<std::size_t> &changed);

    /**
     * Solves the current state; writes the load steps that 'Output/Write
     * VTU' asks for with @p vtu if given (output is not timed).
     */
    Result
    solve(report::VtuWriter *vtu);

    /// The discretization.
    const solver::Discretization &
    discretization() const
    {
      return *model;
    }

    /// The displacement of the last solve (m).
    const Vector<double> &
    solution() const
    {
      return solver->solution();
    }

  private:
    /// The timer receiving this model's sections.
    TimerOutput                             timer;
    const scene::Scene                     &scene;
    const coarsening::Coarsener            *coarsener;
    std::unique_ptr<solver::Discretization> model;
    std::unique_ptr<solver::StaticSolver>   solver;
    /// Wall time of setup (and coarsening) not yet charged to a solve.
    double pending_time = 0;
    /// Coarsening time and updated cells not yet reported by a solve.
    double       pending_coarsening = 0;
    unsigned int pending_cells      = 0;
  };

  /// Peak resident memory of this process in MiB (2^20 bytes; the
  /// summaries' key keeps the name peak_memory_mb).
  double
  peak_memory_mb();

  /**
   * Checks what a ddfem model of @p scene at coarsening level @p level
   * with polynomial degree @p degree needs besides its database, before the
   * database is prepared (which may fit for minutes): builds the model with
   * naive materials (the same mesh, supports, loads and probes) and
   * discards it. Throws ExcMessage like the ModelRun constructor, e.g. for
   * a degree other than 1.
   */
  void
  check_coarse_model(const scene::Scene                     &scene,
                     const unsigned int                      degree,
                     const unsigned int                      level,
                     const double                            point_offset,
                     const solver::StaticSolver::Parameters &parameters,
                     solver::LinearSolver                   &linear_solver);
} // namespace ddfem::app

#endif
