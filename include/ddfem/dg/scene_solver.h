#ifndef ddfem_dg_scene_solver_h
#define ddfem_dg_scene_solver_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/timer.h>
#include <deal.II/grid/tria.h>

#include <ddfem/dg/parameters.h>
#include <ddfem/dg/system.h>
#include <ddfem/scene/scene.h>
#include <ddfem/solver/linear_solver.h>
#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

namespace ddfem::dg
{
  using namespace dealii;

  /**
   * A scene solved with the DG method (Method = dg): the voxel mesh with one
   * hexahedron per solid voxel, the palette's Lame parameters per cell, the
   * scene's boundary conditions (fixed, sliding, displacement and rotation
   * as Dirichlet data, weak or strong; traction, pressure and body force as
   * loads) and a System<3>.
   */
  class SceneSolver
  {
  public:
    /**
     * A solver for @p scene with @p parameters (both must outlive it).
     * Throws ExcMessage if DG/Dirichlet = strong is combined with FE_DGP,
     * which has no nodes on the boundary to constrain, or if a rotation
     * turns by more than 90 degrees per load step of the corotated
     * formulation or in the one solve of the linear one
     * (BoundaryConditions::check_rotation_steps()). The systems are solved
     * with @p linear_solver (the scene's 'Linear solver', which must
     * outlive it too).
     */
    SceneSolver(const scene::Scene   &scene,
                const Parameters     &parameters,
                solver::LinearSolver &linear_solver);

    /**
     * Builds the mesh and the system and settles the penalty. Throws
     * ExcMessage on bad input (a condition whose region misses the solid or
     * that would do nothing there,
     * conditions that leave rigid motions free, loads that are not finite,
     * a fixed penalty that is too small), before anything is written.
     */
    void
    setup();

    /// The solver of the linear systems, as setup() chose it: "cholesky of
    /// the penalty check" for a linear system whose definiteness check
    /// passed (solved with that check's factor), else the scene's 'Linear
    /// solver', whose 'direct' factorizes with sparse Cholesky first
    /// (System::cholesky_first).
    std::string
    linear_solver_name() const;

    /// Solves (linear or corotated); returns the number of linear solves.
    unsigned int
    solve();

    /// The displacement at @p p; throws ExcMessage naming
    /// Geometry/Probe points if @p p is outside the solid.
    Tensor<1, 3>
    point_value(const Point<3> &p) const;

    /// Writes the (discontinuous) displacement and material id to @p file.
    void
    write_vtu(const std::string &file) const;

    /**
     * Adds the DG entries to @p summary: method, flux, element, degree,
     * penalty, definiteness, dofs, cells, nonzeros, times and solves.
     */
    void
    summarize(nlohmann::json &summary) const;

    /// The DG system (valid after setup()).
    const System<3> &
    system() const
    {
      return *dg;
    }

    /// The outcome of the definiteness check at the settled penalty.
    Definiteness definiteness = Definiteness::not_checked;

  private:
    /// The point of @p cell at @p unit_point of the reference cell.
    Point<3>
    cell_point(const Triangulation<3>::active_cell_iterator &cell,
               const Point<3>                               &unit_point) const;

    /**
     * The points where Dirichlet conditions act on @p cell: with weak
     * conditions the Gauss points of its faces, with strong ones the
     * element's support points (needs the element). Interior ones count
     * too: a box region holds what it contains, as in CG.
     */
    std::vector<Point<3>>
    dirichlet_points(const Triangulation<3>::active_cell_iterator &cell) const;

    /**
     * Checks the scene's conditions on the mesh before the system is built:
     * loads and Dirichlet data are finite at every point of the assembly
     * (whose worker threads could not report an error), every condition
     * acts somewhere, and the Dirichlet conditions fix all six rigid
     * motions of every face-connected part (the only coupling DG has).
     * Throws ExcMessage naming the parameter otherwise.
     */
    void
    check_conditions() const;

    const scene::Scene   &scene;
    const Parameters     &parameters;
    solver::LinearSolver &linear_solver;
    /// Receives the linear solver's timing sections (never printed).
    TimerOutput                       timer_output;
    Triangulation<3>                  triangulation;
    ProblemData<3>                    data;
    std::unique_ptr<FiniteElement<3>> element;
    std::unique_ptr<System<3>>        dg;
    unsigned int                      linear_solves = 0;
    /// Iterations of all linear solves, as LinearSolver::solve() counts
    /// them: CG iterations, plus 1 per direct solve or solve with a new
    /// Cholesky factor.
    unsigned int linear_iterations = 0;
    double       setup_time = 0, solve_time = 0;
    /// linear_solver_name().
    std::string solver_name;
  };
} // namespace ddfem::dg

#endif
