#include <deal.II/base/utilities.h>

#include <ddfem/app/model_run.h>
#include <ddfem/base/statistics.h>
#include <ddfem/report/vertex_error.h>

#include <algorithm>
#include <optional>
#include <sstream>

namespace ddfem::app
{
  namespace
  {
    /// The largest displacement of any node (support point) in @p u (m).
    double
    max_node_displacement(const solver::Discretization &model,
                          const Vector<double>         &u)
    {
      double                               max_u = 0;
      const FiniteElement<3>              &fe    = model.fe;
      std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
      for (const auto &cell : model.dof_handler.active_cell_iterators())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int i = 0; i < dofs.size(); ++i)
            if (fe.system_to_component_index(i).first == 0)
              {
                const unsigned int node =
                  fe.system_to_component_index(i).second;
                Tensor<1, 3> d;
                for (unsigned int c = 0; c < 3; ++c)
                  d[c] = u(dofs[fe.component_to_system_index(c, node)]);
                max_u = std::max(max_u, d.norm());
              }
        }
      return max_u;
    }



    /// The median, 99th percentile and largest entry of @p v (quantile()).
    std::array<double, 3>
    quantiles(const Vector<double> &v)
    {
      std::vector<double> sorted(v.begin(), v.end());
      if (sorted.empty())
        return {{0, 0, 0}};
      std::sort(sorted.begin(), sorted.end());
      return {{quantile(sorted, 0.5), quantile(sorted, 0.99), sorted.back()}};
    }
  } // namespace


  nlohmann::json
  to_json(const std::vector<Probe> &probes)
  {
    nlohmann::json json = nlohmann::json::array();
    for (const auto &[x, u] : probes)
      json.push_back(
        {{"point", {x[0], x[1], x[2]}}, {"displacement", {u[0], u[1], u[2]}}});
    return json;
  }



  nlohmann::json
  ModelRun::Result::to_json() const
  {
    nlohmann::json json;
    json["converged"]               = statistics.converged;
    json["from_last_state"]         = statistics.from_last_state;
    json["failed_start_iterations"] = statistics.failed_start_iterations;
    json["load_steps"]              = statistics.load_steps;
    json["step_cuts"]               = statistics.step_cuts;
    json["newton_iterations"]       = statistics.newton_iterations;
    json["linear_iterations"]       = statistics.linear_iterations;
    json["direct_solves"]           = statistics.direct_solves;
    json["preconditioner_setups"]   = statistics.preconditioner_setups;
    json["regularized_iterations"]  = statistics.regularized_iterations;
    if (!statistics.converged)
      json["failure"] = statistics.failure;
    json["min_J"]            = min_J;
    json["min_vertex_J"]     = statistics.min_vertex_J;
    json["principal_strain"] = {{"median", strain_quantiles[0]},
                                {"p99", strain_quantiles[1]},
                                {"max", strain_quantiles[2]}};
    json["max_displacement"] = max_displacement;
    json["coarsening_time_s"] =
      coarse ? nlohmann::json(coarsening_time) : nlohmann::json();
    json["cells_updated"]        = cells_updated;
    json["wall_time_s"]          = wall_time;
    json["time_per_iteration_s"] = time_per_iteration();
    json["phase_wall_time_s"]    = phases;
    json["probes"]               = app::to_json(probes);
    return json;
  }



  ModelRun::ModelRun(const scene::Scene                     &scene,
                     const unsigned int                      degree,
                     const coarsening::Coarsener            *coarsener,
                     const solver::StaticSolver::Parameters &parameters,
                     solver::LinearSolver                   &linear_solver,
                     ConditionalOStream                     &log)
    : timer(log, TimerOutput::never, TimerOutput::wall_times)
    , scene(scene)
    , coarsener(coarsener)
  {
    Timer total;
    {
      TimerOutput::Scope scope(timer, "setup");
      model = coarsener == nullptr ?
                std::make_unique<solver::Discretization>(scene, degree) :
                std::make_unique<solver::Discretization>(
                  scene, degree, coarsener->level(), coarsener->point_offset());
    }
    if (coarsener != nullptr)
      {
        TimerOutput::Scope scope(timer, "coarsening");
        Timer              lookups;
        coarsener->coarsen(scene.grid, *model);
        pending_coarsening = lookups.wall_time();
        pending_cells      = model->triangulation.n_active_cells();
      }
    {
      TimerOutput::Scope scope(timer, "setup");
      solver = std::make_unique<solver::StaticSolver>(*model,
                                                      scene.boundary_conditions,
                                                      parameters,
                                                      linear_solver,
                                                      timer,
                                                      log);
      solver->setup();
      for (const Point<3> &p : scene.probes)
        solver->point_value(solver->solution(), p); // throws if outside
    }
    pending_time = total.wall_time();
  }



  void
  ModelRun::edit(const std::vector<std::size_t> &changed)
  {
    Timer total;
    if (coarsener != nullptr)
      {
        TimerOutput::Scope scope(timer, "coarsening");
        Timer              lookups;
        pending_cells += coarsener->recoarsen(scene.grid, changed, *model);
        pending_coarsening += lookups.wall_time();
      }
    {
      // The fine model's new materials are setup, as its first ones were.
      TimerOutput::Scope scope(timer, "setup");
      if (coarsener == nullptr)
        {
          model->update_voxel_materials(scene, changed);
          pending_cells += changed.size();
        }
      solver->update_materials();
    }
    pending_time += total.wall_time();
  }



  ModelRun::Result
  ModelRun::solve(report::VtuWriter *vtu)
  {
    Result result;
    Timer  total;
    double output_time = 0;
    // The fields of the full load, if written: the strain statistics reuse
    // them.
    std::optional<solver::StaticSolver::CellFields> final_fields;
    result.statistics =
      solver->solve([&](const unsigned int step, const double t) {
        const bool last = t >= 1 - 1e-12;
        if (vtu != nullptr && vtu->writes(last))
          {
            Timer output;
            auto  fields = solver->cell_fields(solver->solution());
            vtu->write(*model, solver->solution(), fields, step, t, last);
            if (last)
              final_fields = std::move(fields);
            output_time += output.wall_time();
          }
      });
    result.wall_time       = pending_time + total.wall_time() - output_time;
    result.coarse          = coarsener != nullptr;
    result.coarsening_time = pending_coarsening;
    result.cells_updated   = pending_cells;
    pending_time = pending_coarsening = 0;
    pending_cells                     = 0;
    for (const auto &[section, seconds] :
         timer.get_summary_data(TimerOutput::total_wall_time))
      result.phases[section] = seconds;
    timer.reset();

    const Vector<double> &u = solver->solution();
    result.min_J            = result.statistics.min_J;
    if (!final_fields)
      final_fields = solver->cell_fields(u);
    result.strain_quantiles = quantiles(final_fields->strain);
    // A coarse element's nodes may lie in void: coarse models are read at
    // the solid's vertices.
    result.max_displacement =
      model->level == 0 ? max_node_displacement(*model, u) :
                          report::max_solid_displacement(scene.grid, *model, u);
    for (const Point<3> &p : scene.probes)
      result.probes.push_back({p, solver->point_value(u, p)});
    return result;
  }



  double
  peak_memory_mb()
  {
    Utilities::System::MemoryStats stats;
    Utilities::System::get_memory_stats(stats);
    return stats.VmHWM / 1024.;
  }



  void
  check_coarse_model(const scene::Scene                     &scene,
                     const unsigned int                      degree,
                     const unsigned int                      level,
                     const double                            point_offset,
                     const solver::StaticSolver::Parameters &parameters,
                     solver::LinearSolver                   &linear_solver)
  {
    std::ostringstream          quiet_stream;
    ConditionalOStream          quiet(quiet_stream, false);
    const coarsening::Coarsener naive(coarsening::CoarseningMethod::naive,
                                      level,
                                      scene.palette,
                                      point_offset);
    const ModelRun              model(
      scene, degree, &naive, parameters, linear_solver, quiet);
  }
} // namespace ddfem::app
