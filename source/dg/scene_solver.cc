#include <deal.II/base/timer.h>
#include <deal.II/numerics/data_out.h>

#include <ddfem/dg/scene_solver.h>
#include <ddfem/report/output.h>
#include <ddfem/solver/probe.h>
#include <ddfem/solver/supports.h>

#include <fstream>
#include <map>

namespace ddfem::dg
{
  SceneSolver::SceneSolver(const scene::Scene   &scene,
                           const Parameters     &parameters,
                           solver::LinearSolver &linear_solver)
    : scene(scene)
    , parameters(parameters)
    , linear_solver(linear_solver)
    , timer_output(std::cout, TimerOutput::never, TimerOutput::wall_times)
  {
    // Checked here, not when parsing: the DG studies impose their
    // conditions weakly whatever DG/Dirichlet says.
    AssertThrow(!(parameters.dirichlet == Parameters::Dirichlet::strong &&
                  parameters.element == Parameters::Element::dgp),
                ExcMessage("DG/Dirichlet = strong needs nodes on the "
                           "boundary: use DG/Element = FE_DGQ, or "
                           "DG/Dirichlet = weak with FE_DGP."));
    // Before the mesh is built (System checks it again, for the studies).
    parameters.check_penalty(parameters.flux, "DG/Flux = babuska-zlamal");
    if (parameters.formulation == Parameters::Formulation::corotated)
      scene.boundary_conditions.check_rotation_steps(parameters.load_steps,
                                                     "DG/Load steps");
    else
      scene.boundary_conditions.check_rotation_steps(
        1,
        "DG/Formulation = linear solves once; corotated takes DG/Load "
        "steps");
  }



  void
  SceneSolver::setup()
  {
    Timer timer;
    scene::make_voxel_mesh(scene.grid, 0, triangulation);
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        const auto &m = scene.palette[cell->material_id()];
        data.materials.push_back({m.mu, m.lambda});
      }
    const scene::BoundaryConditions &bc = scene.boundary_conditions;
    data.dirichlet                      = [&bc](const Point<3>    &p,
                           const unsigned int c,
                           const double       t,
                           double            &value) {
      return bc.prescribed_displacement(p, c, t, value);
    };
    // A box holds what it contains, interior nodes and faces too, as in CG.
    data.dirichlet_inside = true;
    data.traction =
      [&bc](const Point<3> &center, const Point<3> &p, const Tensor<1, 3> &n) {
        return bc.traction(center, p, n);
      };
    if (bc.has_body_force())
      data.body_force = [&bc](const Point<3> &p) { return bc.body_force(p); };

    element = parameters.make_element<3>();
    check_conditions();

    dg =
      std::make_unique<System<3>>(triangulation, *element, 3, parameters, data);
    // A linear system is solved with the factor of its definiteness check
    // where the check ran: the same matrix, factorized once.
    dg->solve_with_check_factor =
      parameters.formulation == Parameters::Formulation::linear;
    definiteness = dg->settle_penalty(1);
    // Otherwise (corotated, or unchecked) the scene's linear solver.
    if (!dg->solves_with_check_factor())
      {
        // A DG solve is a result, not a Newton step: the iterative solvers
        // reduce the residual to round-off (1e-12). 'auto' takes the direct
        // solver where it fits: the corotated iteration stalled at a change of
        // 1e-6 with cg-cholesky's inexact solves at stiffness contrast 1e6
        // (tests/stability/rigid_rotation.cc).
        linear_solver.initialize(dg->dof_handler, timer_output, "direct");
        // A direct solve takes sparse Cholesky where K is positive definite
        // (the corotated matrices mostly are): exact as UMFPACK's LU, and
        // its factorizations share one ordering.
        dg->cholesky_first = (linear_solver.method() == "direct");
        dg->linear_solver  = [this](const SparseMatrix<double> &K,
                                   Vector<double>             &x,
                                   const Vector<double>       &b) {
          try
            {
              linear_iterations += linear_solver.solve(K, x, b, 1e-12);
            }
          catch (const solver::LinearSolver::Failure &failure)
            {
              AssertThrow(
                false,
                ExcMessage(
                  "The DG system (" + std::to_string(K.m()) +
                  " DoFs) could not be solved with Linear solver/Type = " +
                  linear_solver.method() + ": " + failure.what() + ". Either " +
                  unsolvable_system_causes() +
                  (linear_solver.method() == "direct" ?
                      std::string(".") :
                      std::string("; or the iterative solver just "
                                  "failed: try Type = direct."))));
            }
        };
        // Iterative solves leave round-off that can keep the corotated
        // iteration from its tolerance at high stiffness contrast.
        if (linear_solver.method() != "direct")
          dg->stall_hint = " The linear solves were iterative (Linear "
                           "solver/Type = " +
                           linear_solver.method() +
                           "): their round-off can stall the corotated "
                           "iteration too; try Type = direct.";
      }
    solver_name =
      dg->solves_with_check_factor() ? "cholesky of the penalty check" :
      dg->cholesky_first ? "cholesky (UMFPACK where not positive definite)" :
                           linear_solver.method();
    setup_time = timer.wall_time();
  }



  Point<3>
  SceneSolver::cell_point(const Triangulation<3>::active_cell_iterator &cell,
                          const Point<3> &unit_point) const
  {
    // Voxels are axis-aligned boxes from vertex 0 to vertex 7.
    Point<3> x = cell->vertex(0);
    for (unsigned int d = 0; d < 3; ++d)
      x[d] += unit_point[d] * (cell->vertex(7)[d] - cell->vertex(0)[d]);
    return x;
  }



  std::vector<Point<3>>
  SceneSolver::dirichlet_points(
    const Triangulation<3>::active_cell_iterator &cell) const
  {
    // Weak conditions act at the quadrature points of every face (its Gauss
    // points), strong ones at every support point of the element (the cell
    // is an axis-aligned box), as the system asks them
    // (ProblemData::dirichlet_inside).
    std::vector<Point<3>> points;
    if (parameters.dirichlet == Parameters::Dirichlet::weak)
      for (const unsigned int f : cell->face_indices())
        for (const Point<3> &x :
             solver::voxel_face(cell, f).gauss_points(parameters.degree + 1))
          points.push_back(x);
    else
      for (const Point<3> &q : element->get_unit_support_points())
        points.push_back(cell_point(cell, q));
    return points;
  }



  void
  SceneSolver::check_conditions() const
  {
    const scene::BoundaryConditions &bc = scene.boundary_conditions;
    const bool weak = parameters.dirichlet == Parameters::Dirichlet::weak;
    // Weak conditions hold where the continuous model holds.
    if (weak)
      {
        std::vector<Point<3>> centers;
        for (const auto &cell : triangulation.active_cell_iterators())
          centers.push_back(cell->center());
        bc.check_weak_supports(centers,
                               scene.grid.voxel_size(),
                               QGauss<1>(parameters.degree + 1).point(0)[0]);
      }

    // One pass over the cells evaluates the loads and Dirichlet data at the
    // assembly's points (the evaluations throw, naming the parameter, where
    // a value is not finite) and collects where conditions act, and the
    // prescribed components of each face-connected part: DG couples cells
    // through shared faces only.
    const QGauss<3>    cell_quadrature(parameters.degree + 1);
    solver::Components parts = solver::face_connected_parts(triangulation);
    std::vector<scene::BoundaryFace>                           faces;
    std::vector<Point<3>>                                      points;
    std::map<std::size_t, std::vector<solver::ConstrainedRow>> rows;
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        // Weak Dirichlet data is asked at the cell's points too, where it
        // takes the body force off held components.
        if (bc.has_body_force())
          for (const Point<3> &q : cell_quadrature.get_points())
            {
              const Point<3> x = cell_point(cell, q);
              bc.body_force(x);
              double value; // evaluated for the check only
              for (unsigned int d = 0; weak && d < 3; ++d)
                bc.prescribed_displacement(x, d, 1, value);
            }
        for (const unsigned int f : cell->face_indices())
          if (cell->face(f)->at_boundary())
            {
              const scene::BoundaryFace &face =
                faces.emplace_back(solver::voxel_face(cell, f));
              for (const Point<3> &x : face.gauss_points(parameters.degree + 1))
                bc.traction(face.center, x, face.normal);
            }
        const std::size_t part = parts.find(cell->active_cell_index());
        for (const Point<3> &x : dirichlet_points(cell))
          {
            points.push_back(x);
            for (unsigned int d = 0; d < 3; ++d)
              if (double value; bc.prescribed_displacement(x, d, 1, value))
                rows[part].emplace_back(x, d);
          }
      }

    // Every condition must act somewhere.
    bc.check_regions(points,
                     faces,
                     weak ? triangulation.get_vertices() :
                            std::vector<Point<3>>());
    bc.check_effects(points, faces, parameters.degree, weak);

    // The conditions must fix all six rigid motions of every face-connected
    // part. The definiteness check of the penalty cannot be relied on for
    // this: round-off lets a singular matrix pass it.
    solver::require_supported_parts(triangulation, parts, rows, "face");
  }



  unsigned int
  SceneSolver::solve()
  {
    Timer              timer;
    const unsigned int cholesky_before = dg->cholesky_solves;
    linear_solves                      = dg->run();
    // As LinearSolver::solve() counts a direct solve: 1 (the check's
    // factor was new to it).
    linear_iterations += dg->cholesky_solves - cholesky_before;
    solve_time = timer.wall_time();
    return linear_solves;
  }



  std::string
  SceneSolver::linear_solver_name() const
  {
    return solver_name;
  }



  Tensor<1, 3>
  SceneSolver::point_value(const Point<3> &p) const
  {
    return solver::probe_displacement(dg->mapping,
                                      dg->dof_handler,
                                      dg->solution,
                                      p);
  }



  void
  SceneSolver::write_vtu(const std::string &file) const
  {
    DataOut<3>     data_out;
    Vector<double> material_id;
    report::add_displacement_and_materials(data_out,
                                           dg->dof_handler,
                                           dg->solution,
                                           material_id);
    data_out.build_patches(dg->mapping, parameters.degree);
    report::write_vtu_file(data_out, file);
  }



  void
  SceneSolver::summarize(nlohmann::json &summary) const
  {
    summary["method"]            = "dg";
    summary["flux"]              = parameters.flux_name();
    summary["element"]           = parameters.element_name();
    summary["degree"]            = parameters.degree;
    summary["penalty"]           = dg->penalty();
    summary["penalty_automatic"] = parameters.automatic_penalty();
    summary["penalty_doublings"] = dg->penalty_doublings;
    summary["definiteness"]      = to_string(definiteness);
    summary["dirichlet"] =
      parameters.dirichlet == Parameters::Dirichlet::weak ? "weak" : "strong";
    summary["formulation"] =
      parameters.formulation == Parameters::Formulation::linear ? "linear" :
                                                                  "corotated";
    summary["cells"]              = triangulation.n_active_cells();
    summary["dofs"]               = dg->dof_handler.n_dofs();
    summary["nonzeros"]           = dg->matrix.n_nonzero_elements();
    summary["linear_solver"]      = linear_solver_name();
    summary["linear_iterations"]  = linear_iterations;
    summary["linear_solves"]      = linear_solves;
    summary["cholesky_solves"]    = dg->cholesky_solves;
    summary["time_setup_s"]       = setup_time;
    summary["time_integration_s"] = dg->integration_time;
    summary["time_assembly_s"]    = dg->assembly_time;
    summary["time_solve_s"]       = solve_time;
  }
} // namespace ddfem::dg
