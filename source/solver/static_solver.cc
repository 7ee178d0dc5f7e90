#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/work_stream.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <ddfem/base/cell_values.h>
#include <ddfem/base/parsing.h>
#include <ddfem/base/statistics.h>
#include <ddfem/material/kernel.h>
#include <ddfem/scene/scene.h>
#include <ddfem/solver/cell_kernel.h>
#include <ddfem/solver/probe.h>
#include <ddfem/solver/static_solver.h>
#include <ddfem/solver/supports.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <memory>

namespace ddfem::solver
{
  LoadSteps::LoadSteps(const unsigned int n_steps, const double minimum_step)
    : nominal_step(1. / n_steps)
    , minimum(minimum_step * nominal_step)
    , t(0)
    , step(nominal_step)
  {}



  bool
  LoadSteps::done() const
  {
    return t >= 1 - 1e-12;
  }



  double
  LoadSteps::current() const
  {
    return t;
  }



  double
  LoadSteps::next() const
  {
    return std::min(1., t + step);
  }



  void
  LoadSteps::accept()
  {
    t = next();
    if (++successes_since_cut >= 2 && step < nominal_step)
      {
        step                = std::min(nominal_step, 2 * step);
        successes_since_cut = 0;
      }
  }



  bool
  LoadSteps::cut()
  {
    // Half the increment tried, min(step, 1 - t): exactly half of step
    // where it did not end at 1, so that doubling back restores it.
    step                = std::min(step, 1 - t) / 2;
    successes_since_cut = 0;
    return step >= minimum;
  }



  bool
  LoadSteps::is_cut() const
  {
    return step < nominal_step;
  }



  namespace
  {
    constexpr double infinity = std::numeric_limits<double>::infinity();

    /// Per-thread scratch space of the assembly loop.
    struct ScratchData
    {
      ScratchData(const Mapping<3>       &mapping,
                  const FiniteElement<3> &fe,
                  const Quadrature<3>    &quadrature)
        : fe_values(mapping,
                    fe,
                    quadrature,
                    update_gradients | update_JxW_values)
        , local_u(fe.n_dofs_per_cell())
      {}
      ScratchData(const ScratchData &other)
        : fe_values(other.fe_values.get_mapping(),
                    other.fe_values.get_fe(),
                    other.fe_values.get_quadrature(),
                    other.fe_values.get_update_flags())
        , local_u(other.local_u.size())
      {}
      FEValues<3>    fe_values;
      Vector<double> local_u;
    };

    /// What one cell hands to the (serial, ordered) copier.
    struct CopyData
    {
      std::vector<types::global_dof_index> dofs;
      CellContribution                     contribution;
      bool                                 admissible;
    };

    /// Position (i, j, k) of voxel @p bit in a block of @p width voxels
    /// per direction (Discretization::solid_voxels).
    std::array<unsigned int, 3>
    voxel_position(const unsigned int bit, const unsigned int width)
    {
      return {{bit % width, (bit / width) % width, bit / (width * width)}};
    }

    /// Whether voxel @p v of the block of the cell with active index
    /// @p cell_index is solid.
    bool
    is_solid(const Discretization              &discretization,
             const unsigned int                 cell_index,
             const std::array<unsigned int, 3> &v)
    {
      const unsigned int width = 1u << discretization.level;
      return (discretization.solid_voxels[cell_index] >>
              (v[0] + width * (v[1] + width * v[2]))) &
             1;
    }

    /**
     * The faces of the fine solid's voxels in the block of @p cell that lie
     * on the solid's boundary, where the neighbor voxel is void or outside
     * the grid, whether the cell is a voxel or a coarse block. Each is the
     * voxel's bit (Discretization::solid_voxels) and the face's number in
     * deal.II's order (-x, +x, -y, +y, -z, +z: voxel meshes are
     * axis-aligned and numbered lexicographically).
     */
    std::vector<std::pair<unsigned int, unsigned int>>
    solid_boundary_faces(const Discretization  &discretization,
                         const CellAccessor<3> &cell)
    {
      const unsigned int width = 1u << discretization.level;
      const unsigned int c     = cell.active_cell_index();
      std::vector<std::pair<unsigned int, unsigned int>> faces;
      for (unsigned int bit = 0; bit < width * width * width; ++bit)
        if (is_solid(discretization, c, voxel_position(bit, width)))
          for (const unsigned int f : cell.face_indices())
            {
              auto               v    = voxel_position(bit, width);
              const unsigned int d    = f / 2;
              const bool         down = (f % 2 == 0);
              bool               neighbor_solid;
              if (down ? v[d] > 0 : v[d] + 1 < width)
                {
                  v[d]           = down ? v[d] - 1 : v[d] + 1;
                  neighbor_solid = is_solid(discretization, c, v);
                }
              else if (cell.at_boundary(f))
                neighbor_solid = false;
              else
                {
                  v[d] = down ? width - 1 : 0;
                  // Voxel meshes, fine or coarse, are unrefined.
                  Assert(cell.neighbor(f)->is_active(), ExcInternalError());
                  neighbor_solid =
                    is_solid(discretization,
                             cell.neighbor(f)->active_cell_index(),
                             v);
                }
              if (!neighbor_solid)
                faces.emplace_back(bit, f);
            }
      return faces;
    }

    /**
     * A quadrature rule of the unit cell on voxel @p bit of a block of
     * @p width voxels per direction: the whole voxel (@p face =
     * numbers::invalid_unsigned_int), or its face @p face. The points are
     * those of the Gauss rule with @p n points per direction on the voxel
     * or face; the weights are fractions of the cell's volume, or of the
     * area of a cell face.
     */
    Quadrature<3>
    voxel_quadrature(const unsigned int bit,
                     const unsigned int width,
                     const unsigned int face,
                     const unsigned int n)
    {
      const auto            v = voxel_position(bit, width);
      const QGauss<1>       gauss(n);
      std::vector<Point<3>> points;
      std::vector<double>   weights;
      const bool            volume = (face == numbers::invalid_unsigned_int);
      const unsigned int    normal = volume ? 3 : face / 2;
      // One index per direction; the face normal's runs over a single value.
      for (unsigned int a = 0; a < (normal == 2 ? 1 : n); ++a)
        for (unsigned int b = 0; b < (normal == 1 ? 1 : n); ++b)
          for (unsigned int c = 0; c < (normal == 0 ? 1 : n); ++c)
            {
              const std::array<unsigned int, 3> index = {{c, b, a}};
              Point<3>                          x;
              double                            w = 1;
              for (unsigned int d = 0; d < 3; ++d)
                if (d == normal)
                  x[d] = (v[d] + face % 2) / double(width);
                else
                  {
                    x[d] = (v[d] + gauss.point(index[d])[0]) / width;
                    w *= gauss.weight(index[d]) / width;
                  }
              points.push_back(x);
              weights.push_back(w);
            }
      return Quadrature<3>(points, weights);
    }
  } // namespace



  void
  StaticSolver::Parameters::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Nonlinear solver");
    prm.declare_entry(
      "Load steps",
      "10",
      Patterns::Integer(1, 10000),
      "Number of equal load increments from load factor 0 to 1.");
    prm.declare_entry(
      "Minimum load step",
      "1e-3",
      Patterns::Double(1e-12, 1),
      "Failed increments are halved; the solve stops with an error "
      "once an increment would be smaller than this fraction of the "
      "nominal one.");
    prm.declare_entry(
      "Maximum Newton iterations",
      "30",
      Patterns::Integer(1, 1000),
      "Newton iterations per load increment before the increment "
      "counts as failed (and is cut): 1 to 1000.");
    prm.declare_entry(
      "Newton tolerance",
      "1e-8",
      Patterns::Double(1e-14, 1e-2),
      "From 1e-14 to 1e-2. Converged when the residual at the free unknowns is this "
      "fraction of the largest of (the largest residual seen in the "
      "increment, the external load at the free unknowns at the step's load "
      "factor), or when the full Newton "
      "step with the unshifted tangent, before the line search, changes no "
      "unknown by more than 1e-13 of the bounding box's diagonal (a "
      "residual of round-off in stiff parts).");
    prm.declare_entry(
      "Start after edit",
      "last state",
      Patterns::Selection("last state|rest"),
      "Where the solve after a material edit (Layout/Edits) starts. 'last "
      "state': Newton's method at the full load from the equilibrium "
      "before the edit, then the load steps from rest only if that fails. "
      "'rest': the load steps from rest, as in the first solve.");
    prm.leave_subsection();
  }



  void
  StaticSolver::Parameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Nonlinear solver");
    load_steps            = prm.get_integer("Load steps");
    minimum_step          = prm.get_double("Minimum load step");
    max_iterations        = prm.get_integer("Maximum Newton iterations");
    tolerance             = prm.get_double("Newton tolerance");
    start_from_last_state = (prm.get("Start after edit") == "last state");
    prm.leave_subsection();
  }



  std::string
  StaticSolver::Statistics::describe() const
  {
    std::string text = from_last_state ? "from the last state after " :
                                         "after " + std::to_string(load_steps) +
                                           " load steps and ";
    text += std::to_string(newton_iterations) + " Newton iterations";
    if (failed_start_iterations > 0)
      text += " (" + std::to_string(failed_start_iterations) +
              " of them in a failed start from the last state)";
    return text;
  }



  StaticSolver::StaticSolver(
    const Discretization            &discretization,
    const scene::BoundaryConditions &boundary_conditions,
    const Parameters                &parameters,
    LinearSolver                    &linear_solver,
    TimerOutput                     &timer,
    ConditionalOStream              &pcout)
    : discretization(discretization)
    , boundary_conditions(boundary_conditions)
    , parameters(parameters)
    , linear_solver(linear_solver)
    , timer(timer)
    , pcout(pcout)
  {
    boundary_conditions.check_rotation_steps(parameters.load_steps,
                                             "Nonlinear solver/Load steps");
  }



  void
  StaticSolver::update_materials()
  {
    // The scale of round-off in energy sums: sum of (mu + |lambda| + C) dV.
    stiffness_volume = 0;
    for (const auto &cell : discretization.dof_handler.active_cell_iterators())
      for (unsigned int q = 0; q < discretization.quadrature.size(); ++q)
        {
          const auto &m = discretization.material(cell->active_cell_index(), q);
          stiffness_volume += (m.mu + std::abs(m.lambda) + m.anisotropy) *
                              discretization.quadrature.weight(q) *
                              cell->measure();
        }
    // The old tangents' factor or multigrid hierarchy would cost more CG
    // iterations than its setup (measured on the shoe's edits,
    // doc/coarsening.md, "Solves after an edit").
    linear_solver.reset();
  }



  void
  StaticSolver::setup()
  {
    const DoFHandler<3>          &dof_handler = discretization.dof_handler;
    const FiniteElement<3>       &fe          = discretization.fe;
    const types::global_dof_index n           = dof_handler.n_dofs();

    // Loads act on the fine solid at every level: its voxels, and its
    // boundary faces with their centers and outward normals.
    const unsigned int width       = 1u << discretization.level;
    const auto         face_center = [&](const CellAccessor<3> &cell,
                                 const unsigned int     bit,
                                 const unsigned int     face) {
      const auto v = voxel_position(bit, width);
      Point<3>   x = cell.vertex(0);
      for (unsigned int d = 0; d < 3; ++d)
        x[d] += cell.extent_in_direction(d) *
                (v[d] + (d == face / 2 ? face % 2 : 0.5)) / width;
      return x;
    };
    const auto face_normal = [](const unsigned int face) {
      Tensor<1, 3> normal;
      normal[face / 2] = (face % 2 == 0) ? -1 : 1;
      return normal;
    };

    // The fine solid's boundary faces of every cell and their centers,
    // where tractions act.
    const bool has_traction = boundary_conditions.has_traction();
    std::vector<std::vector<std::pair<unsigned int, unsigned int>>>
      boundary_faces(discretization.triangulation.n_active_cells());
    std::vector<scene::BoundaryFace> load_faces;
    if (has_traction)
      for (const auto &cell :
           discretization.triangulation.active_cell_iterators())
        {
          auto &faces = boundary_faces[cell->active_cell_index()];
          faces       = solid_boundary_faces(discretization, *cell);
          for (const auto &[bit, face] : faces)
            load_faces.push_back({face_center(*cell, bit, face),
                                  face_normal(face),
                                  cell->extent_in_direction(0) / width});
        }

    // Every condition must act somewhere, and supports where the fine
    // model has them.
    if (discretization.level > 0)
      boundary_conditions.check_coarse_supports(
        discretization.extent,
        discretization.triangulation.begin_active()->extent_in_direction(0) /
          width,
        width);
    // Dirichlet nodes: every support point a condition covers (vertices,
    // and at degree 2 edge, face and cell midpoints too).
    std::vector<Point<3>> points(n);
    DoFTools::map_dofs_to_support_points(discretization.mapping,
                                         dof_handler,
                                         points);
    boundary_conditions.check_regions(points, load_faces);
    // A coarse grid may lack the nodes where a condition keeps a component
    // to itself in the fine model: coarse models leave this check to the
    // fine voxels (check_voxel_scene(), or a compare run's fine model).
    if (discretization.level == 0)
      boundary_conditions.check_effects(points, load_faces, fe.degree, false);
    const std::vector<unsigned int> component = dof_components(dof_handler);
    dirichlet_dofs.clear();
    for (types::global_dof_index i = 0; i < n; ++i)
      {
        double value;
        if (boundary_conditions.prescribed_displacement(
              points[i], component[i], 1., value))
          dirichlet_dofs.push_back({i, points[i], component[i]});
      }
    check_supports();

    DynamicSparsityPattern dsp(n, n);
    DoFTools::make_sparsity_pattern(dof_handler, dsp);
    pattern.copy_from(dsp);
    system_matrix.reinit(pattern);
    displacement.reinit(n);
    at_full_load = false;
    linear_solver.initialize(dof_handler, timer);
    update_materials();

    // Dead external loads at t = 1: the body force over the fine solid's
    // voxels and the tractions over its boundary faces, weighted with the
    // cell's shape functions at the fine Gauss points. A coarse model thus
    // carries the fine model's load restricted to its displacements, also
    // where its blocks are partly void. One rule per voxel of a block, and
    // per voxel face.
    external_force.reinit(n);
    const unsigned int n_gauss        = fe.degree + 1;
    const bool         has_body_force = boundary_conditions.has_body_force();
    std::vector<std::unique_ptr<FEValues<3>>> voxel_values, face_values;
    for (unsigned int bit = 0; bit < width * width * width; ++bit)
      {
        if (has_body_force)
          voxel_values.push_back(std::make_unique<FEValues<3>>(
            discretization.mapping,
            fe,
            voxel_quadrature(
              bit, width, numbers::invalid_unsigned_int, n_gauss),
            update_values | update_quadrature_points | update_JxW_values));
        if (has_traction)
          for (unsigned int face = 0; face < 6; ++face)
            face_values.push_back(std::make_unique<FEValues<3>>(
              discretization.mapping,
              fe,
              voxel_quadrature(bit, width, face, n_gauss),
              update_values | update_quadrature_points));
      }

    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    // Adds the load density load(q) with the weights weight(q).
    const auto add_load =
      [&](const FEValues<3> &values, const auto &load, const auto &weight) {
        for (unsigned int q = 0; q < values.n_quadrature_points; ++q)
          {
            const Tensor<1, 3> f = load(q) * weight(q);
            for (unsigned int i = 0; i < dofs.size(); ++i)
              external_force(dofs[i]) +=
                f[component[dofs[i]]] * values.shape_value(i, q);
          }
      };
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        cell->get_dof_indices(dofs);
        if (has_body_force)
          for (unsigned int bit = 0; bit < width * width * width; ++bit)
            if (is_solid(discretization,
                         cell->active_cell_index(),
                         voxel_position(bit, width)))
              {
                const TranslatedValues<3> on =
                  reinit_thread_independently(*voxel_values[bit],
                                              cell,
                                              dof_handler.begin_active());
                const FEValues<3> &values = on.values;
                add_load(
                  values,
                  [&](const unsigned int q) {
                    return boundary_conditions.body_force(
                      values.quadrature_point(q) + on.shift);
                  },
                  [&](const unsigned int q) { return values.JxW(q); });
              }
        if (has_traction)
          for (const auto &[bit, face] :
               boundary_faces[cell->active_cell_index()])
            {
              FEValues<3> &values = *face_values[6 * bit + face];
              values.reinit(cell);
              const Point<3> center = face_center(*cell, bit, face);
              // The weights are fractions of the cell face's area.
              const unsigned int d   = face / 2;
              const double cell_area = cell->extent_in_direction((d + 1) % 3) *
                                       cell->extent_in_direction((d + 2) % 3);
              add_load(
                values,
                [&](const unsigned int q) {
                  return boundary_conditions.traction(
                    center, values.quadrature_point(q), face_normal(face));
                },
                [&](const unsigned int q) {
                  return values.get_quadrature().weight(q) * cell_area;
                });
            }
      }
  }



  void
  StaticSolver::check_supports() const
  {
    // The rows of each cell's Dirichlet nodes.
    std::map<types::global_dof_index, const DirichletDof *> dirichlet;
    for (const DirichletDof &d : dirichlet_dofs)
      dirichlet[d.index] = &d;
    std::vector<std::vector<ConstrainedRow>> cell_rows(
      discretization.triangulation.n_active_cells());
    std::vector<types::global_dof_index> dofs(
      discretization.fe.n_dofs_per_cell());
    for (const auto &cell : discretization.dof_handler.active_cell_iterators())
      {
        cell->get_dof_indices(dofs);
        for (const auto dof : dofs)
          if (const auto d = dirichlet.find(dof); d != dirichlet.end())
            cell_rows[cell->active_cell_index()].emplace_back(
              d->second->point, d->second->component);
      }
    require_supported_mesh(discretization.triangulation, cell_rows);
  }



  double
  StaticSolver::assemble(const Vector<double>            &u,
                         const double                     t,
                         Vector<double>                  *residual,
                         const AffineConstraints<double> *constraints,
                         SparseMatrix<double>            *tangent,
                         Vector<double>                  *newton_rhs,
                         double                          &min_J) const
  {
    const auto what = tangent  ? material::KernelOutput::tangent :
                      residual ? material::KernelOutput::stress :
                                 material::KernelOutput::energy;
    if (residual)
      *residual = 0;
    if (tangent)
      {
        *tangent    = 0;
        *newton_rhs = 0;
      }
    double strain_energy  = 0;
    bool   admissible     = true;
    min_J                 = std::numeric_limits<double>::max();
    const std::size_t n_q = discretization.quadrature.size();
    // Every cell of the grid is a translate of the first one, whose values
    // it then takes (reinit_thread_independently()).
    const auto reference = discretization.dof_handler.begin_active();

    const auto worker =
      [&](const typename DoFHandler<3>::active_cell_iterator &cell,
          ScratchData                                        &scratch,
          CopyData                                           &copy) {
        reinit_thread_independently(scratch.fe_values, cell, reference);
        cell->get_dof_values(u, scratch.local_u);
        copy.dofs.resize(scratch.local_u.size());
        cell->get_dof_indices(copy.dofs);
        copy.admissible = integrate_cell(
          scratch.fe_values,
          scratch.local_u,
          &discretization.material_points[cell->active_cell_index() * n_q],
          what,
          copy.contribution);
      };
    const auto copier = [&](const CopyData &copy) {
      strain_energy += copy.contribution.energy;
      min_J      = min_or_nan(min_J, copy.contribution.min_J);
      admissible = admissible && copy.admissible;
      if (!copy.admissible)
        return;
      if (residual)
        for (unsigned int i = 0; i < copy.dofs.size(); ++i)
          (*residual)(copy.dofs[i]) += copy.contribution.residual(i);
      if (tangent)
        {
          Vector<double> local_rhs(copy.contribution.residual);
          local_rhs *= -1;
          constraints->distribute_local_to_global(copy.contribution.tangent,
                                                  local_rhs,
                                                  copy.dofs,
                                                  *tangent,
                                                  *newton_rhs,
                                                  true);
        }
    };
    WorkStream::run(discretization.dof_handler.begin_active(),
                    discretization.dof_handler.end(),
                    worker,
                    copier,
                    ScratchData(discretization.mapping,
                                discretization.fe,
                                discretization.quadrature),
                    CopyData());

    if (!admissible)
      return infinity;
    if (residual)
      residual->add(-t, external_force);
    if (tangent)
      for (types::global_dof_index i = 0; i < u.size(); ++i)
        if (!constraints->is_constrained(i))
          (*newton_rhs)(i) += t * external_force(i);
    return strain_energy - t * (external_force * u);
  }



  double
  StaticSolver::energy(const Vector<double> &u, const double t) const
  {
    double min_J;
    return assemble(u, t, nullptr, nullptr, nullptr, nullptr, min_J);
  }



  void
  StaticSolver::residual_and_tangent(const Vector<double> &u,
                                     const double          t,
                                     Vector<double>       &residual,
                                     SparseMatrix<double> &tangent) const
  {
    AffineConstraints<double> none;
    none.close();
    Vector<double> rhs(u.size());
    residual.reinit(u.size());
    tangent.reinit(pattern);
    double min_J;
    assemble(u, t, &residual, &none, &tangent, &rhs, min_J);
  }



  bool
  StaticSolver::newton(const double    t,
                       Vector<double> &u,
                       Statistics     &statistics)
  {
    const types::global_dof_index n = u.size();
    Vector<double> residual(n), rhs(n), du(n), trial(n), diagonal(n);
    double         reference          = 0;
    double         newton_step        = infinity;
    unsigned int   regularized        = 0;
    const double   length             = discretization.extent.norm();
    const auto     free_residual_norm = [&](Vector<double> &r) {
      for (const DirichletDof &d : dirichlet_dofs)
        r(d.index) = 0;
      return r.l2_norm();
    };
    // Loads on held nodes go into reactions, not into the residual.
    Vector<double> free_load(external_force);
    const double   free_load_norm = free_residual_norm(free_load);
    // Whether residual, energy_now and min_J already hold u's: the line
    // search assembles them for the state it accepts. The tangent pass
    // (which assembles them again, to the bit) then runs only if that
    // state is neither converged nor the last Newton may take.
    bool           state_known = false;
    double         min_J = 0, energy_now = 0;
    Vector<double> trial_residual(n);

    // Up to max_iterations Newton steps; the state after the last one is
    // tested for convergence too.
    for (unsigned int iteration = 0;; ++iteration)
      {
        // Dirichlet values at t, as the increment still missing from u.
        AffineConstraints<double> constraints;
        double                    gap = 0;
        for (const DirichletDof &d : dirichlet_dofs)
          {
            double value = 0;
            boundary_conditions.prescribed_displacement(d.point,
                                                        d.component,
                                                        t,
                                                        value);
            constraints.add_line(d.index);
            constraints.set_inhomogeneity(d.index, value - u(d.index));
            gap = std::max(gap, std::abs(value - u(d.index)));
          }
        constraints.close();
        const bool on_boundary_values = (gap <= 1e-12 * length);

        const auto assemble_tangent = [&]() {
          TimerOutput::Scope scope(timer, "assembly");
          energy_now = assemble(
            u, t, &residual, &constraints, &system_matrix, &rhs, min_J);
        };
        if (!state_known)
          assemble_tangent();
        const double residual_norm = free_residual_norm(residual);
        reference = std::max({reference, residual_norm, t * free_load_norm});

        pcout << "    Newton " << std::setw(2) << iteration
              << ": |R| = " << std::scientific << std::setprecision(3)
              << residual_norm << ", E = " << std::setprecision(5) << energy_now
              << std::defaultfloat;
        // Converged: small residual, or a Newton correction at round-off
        // level (with residuals dominated by round-off in stiff parts).
        if (on_boundary_values &&
            (residual_norm <= parameters.tolerance * reference ||
             newton_step <= 1e-13 * length))
          {
            pcout << "  converged" << std::endl;
            statistics.min_J = min_J;
            return true;
          }
        if (iteration == parameters.max_iterations)
          break;
        ++statistics.newton_iterations;
        if (state_known)
          {
            // The same residual again, with the tangent and its right-hand
            // side; its held entries are zeroed, as above, for the slope.
            assemble_tangent();
            free_residual_norm(residual);
          }

        // Newton direction; shift the tangent by a multiple of its diagonal
        // while the solve fails or the direction does not descend.
        for (types::global_dof_index i = 0; i < n; ++i)
          diagonal(i) = system_matrix.diag_element(i);
        double             shift             = 0;
        unsigned int       linear_iterations = 0;
        const unsigned int direct_solves     = linear_solver.direct_solves();
        const unsigned int setups   = linear_solver.preconditioner_setups();
        bool               descends = true;
        // Why the tangent was shifted, then why the last shift failed.
        std::string why_shifted, why_failed;
        // Whether a failed solve printed its reason on the log's line.
        bool reason_printed = false;
        while (true)
          {
            bool solved = false;
            try
              {
                linear_iterations +=
                  linear_solver.solve(system_matrix,
                                      du,
                                      rhs,
                                      on_boundary_values ?
                                        0.1 * residual_norm / reference :
                                        1.,
                                      &u);
                constraints.distribute(du);
                solved = true;
              }
            catch (LinearSolver::Failure &failure)
              {
                linear_iterations += failure.iterations;
                why_failed =
                  "the linear solve failed: " + std::string(failure.what());
                pcout << (reason_printed ? "" : "\n      ") << failure.what()
                      << "; ";
                reason_printed = true;
              }
            if (solved && (!on_boundary_values || residual * du < 0))
              break;
            if (solved)
              why_failed = "the Newton direction did not descend (an "
                           "indefinite tangent, as near buckling)";
            if (shift == 0)
              why_shifted = why_failed;
            const double new_shift = (shift == 0 ? 1e-4 : 10 * shift);
            if (new_shift > 1e4)
              {
                descends       = false;
                newton_failure = why_failed +
                                 " even with the tangent shifted by " +
                                 format_number(shift) + " times its diagonal";
                break;
              }
            for (types::global_dof_index i = 0; i < n; ++i)
              if (!constraints.is_constrained(i))
                system_matrix.diag_element(i) +=
                  (new_shift - shift) * std::abs(diagonal(i));
            shift = new_shift;
          }
        // The linear work counts whether or not it found a direction.
        statistics.linear_iterations += linear_iterations;
        statistics.direct_solves +=
          linear_solver.direct_solves() - direct_solves;
        statistics.preconditioner_setups +=
          linear_solver.preconditioner_setups() - setups;
        if (shift > 0)
          ++statistics.regularized_iterations;
        if (!descends)
          {
            pcout << (reason_printed ? "" : ", ")
                  << "no descent direction found" << std::endl;
            return false;
          }
        if (!on_boundary_values)
          pcout << " [boundary values]";
        if (shift > 0)
          {
            pcout << " [tangent shifted by " << shift << " diag]";
            // Shifted steps converge slowly at best; near a bifurcation a
            // shorter load increment is the better cure.
            if (++regularized > max_regularized_iterations)
              {
                newton_failure =
                  "more than " + std::to_string(max_regularized_iterations) +
                  " of its iterations needed a shifted tangent; in the "
                  "last, unshifted, " +
                  why_shifted;
                pcout << ", too many shifted iterations" << std::endl;
                return false;
              }
          }
        if (linear_solver.method() != "direct")
          pcout << ", " << linear_iterations << " CG its";
        // A shifted step is shorter than Newton's: no convergence measure.
        newton_step = (shift == 0 ? du.linfty_norm() : infinity);

        // Backtracking line search. While the boundary values are being
        // reached, any admissible state is accepted. Then the energy must
        // decrease sufficiently (Armijo); where the expected decrease is at
        // round-off level of the energy, a decreasing residual is accepted
        // instead, provided the energy rises by no more than that level.
        TimerOutput::Scope scope(timer, "line search");
        const double       slope = residual * du;
        const double       noise =
          1e-14 * (stiffness_volume + std::abs(t * (external_force * u)));
        double alpha    = 1;
        bool   accepted = false, admissible = false;
        // Whether the residual test, not Armijo's, accepted the step (the
        // log marks it).
        bool by_residual = false;
        for (unsigned int k = 0; k < 30; ++k, alpha *= 0.5)
          {
            trial = u;
            trial.add(alpha, du);
            // With the residual, which the next iteration's convergence test
            // needs if this step is accepted.
            double       trial_min_J;
            const double energy_trial = assemble(trial,
                                                 t,
                                                 &trial_residual,
                                                 nullptr,
                                                 nullptr,
                                                 nullptr,
                                                 trial_min_J);
            if (!std::isfinite(energy_trial))
              continue;
            admissible = true;
            accepted   = !on_boundary_values ||
                       energy_trial <= energy_now + 1e-4 * alpha * slope;
            if (!accepted && alpha * std::abs(slope) <= 1e3 * noise &&
                energy_trial <= energy_now + 1e3 * noise)
              {
                Vector<double> free_trial_residual(trial_residual);
                by_residual =
                  free_residual_norm(free_trial_residual) < residual_norm;
                accepted = by_residual;
              }
            if (accepted)
              {
                energy_now = energy_trial;
                min_J      = trial_min_J;
                break;
              }
          }
        if (!accepted)
          {
            // Toward the boundary values any admissible step is accepted.
            newton_failure = admissible ?
                               "the line search found no step along its "
                               "direction that lowers the energy" :
                               std::string(on_boundary_values ?
                                             "every step along the Newton "
                                             "direction" :
                                             "every step toward the boundary "
                                             "values") +
                                 ", down to 2^-29 of it, made a cell "
                                 "inadmissible (det F <= 0)";
            pcout << ", line search failed" << std::endl;
            return false;
          }
        pcout << ", step " << alpha
              << (by_residual ? " [energy at round-off, residual decreased]" :
                                "")
              << std::endl;
        u.swap(trial);
        residual.swap(trial_residual);
        state_known = true;
      }
    pcout << std::endl
          << "    no convergence in " << parameters.max_iterations
          << " Newton iterations" << std::endl;
    newton_failure = "it did not converge in Nonlinear solver/Maximum Newton "
                     "iterations = " +
                     std::to_string(parameters.max_iterations);
    return false;
  }



  StaticSolver::Statistics
  StaticSolver::solve(const std::function<void(unsigned int, double)> &on_step)
  {
    try
      {
        const Statistics statistics = solve_load_path(on_step);
        linear_solver.reset();
        return statistics;
      }
    catch (...)
      {
        linear_solver.reset();
        throw;
      }
  }



  StaticSolver::Statistics
  StaticSolver::solve_load_path(
    const std::function<void(unsigned int, double)> &on_step)
  {
    Statistics  statistics;
    std::string inverted;
    if (at_full_load && parameters.start_from_last_state)
      {
        pcout << "  From the last state: load factor 1" << std::endl;
        Vector<double> u = displacement;
        if (converge(1., u, statistics, inverted))
          {
            statistics.from_last_state = true;
            statistics.converged       = true;
            accept(u, 1., statistics, on_step);
            return statistics;
          }
        pcout << "  No equilibrium from the last state"
              << (inverted.empty() ? "" :
                                     " (Newton's method converged to a "
                                     "state that " +
                                       inverted + ")")
              << "; the load steps start from rest" << std::endl;
        statistics.failed_start_iterations = statistics.newton_iterations;
        statistics.min_J                   = 1;
        // The factor of that far-off state would only cost CG iterations.
        linear_solver.reset();
      }
    at_full_load = false;
    LoadSteps steps(parameters.load_steps, parameters.minimum_step);
    // The last two accepted increments and their load steps (0: none).
    Vector<double> last_increment(displacement.size()),
      previous_increment(displacement.size());
    double last_step = 0, previous_step = 0;
    displacement = 0;
    while (!steps.done())
      {
        const double t = steps.current(), t_new = steps.next();
        pcout << "  Load step " << statistics.load_steps + 1 << ": load factor "
              << t_new << std::endl;

        // Start from the last state extrapolated along the last increment
        // (a line) or the last two (a parabola through the last three
        // states, which follows a rotation's arc where the line cuts its
        // chord), whichever has the lower energy, with the exact boundary
        // values at t_new; from the last state if neither is admissible.
        Vector<double> u = displacement;
        if (last_step > 0)
          {
            const double dt                   = t_new - t;
            const auto   with_boundary_values = [&](Vector<double> &v) {
              for (const DirichletDof &d : dirichlet_dofs)
                boundary_conditions.prescribed_displacement(d.point,
                                                            d.component,
                                                            t_new,
                                                            v(d.index));
              TimerOutput::Scope scope(timer, "assembly");
              return energy(v, t_new);
            };
            // energy() is +infinity where a state is inadmissible.
            Vector<double> line = displacement;
            line.add(dt / last_step, last_increment);
            const double e_line = with_boundary_values(line);
            if (e_line < infinity)
              u = line;
            if (previous_step > 0)
              {
                // Newton's form: the second divided difference times
                // (t_new - t) (t_new - t + last_step).
                const double c =
                  dt * (dt + last_step) / (last_step + previous_step);
                Vector<double> parabola = line;
                parabola.add(c / last_step, last_increment);
                parabola.add(-c / previous_step, previous_increment);
                if (with_boundary_values(parabola) < e_line)
                  u = parabola;
              }
          }
        const double accepted_min_J = statistics.min_J;
        if (converge(t_new, u, statistics, inverted))
          {
            previous_increment.swap(last_increment);
            previous_step  = last_step;
            last_increment = u;
            last_increment -= displacement;
            last_step = t_new - t;
            steps.accept();
            accept(u, t_new, statistics, on_step);
          }
        else if (!inverted.empty())
          {
            // A shorter increment ending at the same load factor leads to
            // the same state, so the solve stops.
            std::ostringstream message;
            message << "the load increment to load factor " << t_new
                    << " converged to a state that " << inverted << ": ";
            if (discretization.level == 0)
              message << "the voxels are too coarse for this "
                         "deformation. Lower the load or refine the grid "
                         "(Geometry/Grid size and Geometry/Voxel size)";
            else
              message << "the coarse cells, blocks of "
                      << (1u << discretization.level)
                      << " voxels per side, are too coarse for this "
                         "deformation. Lower the load, or 'Coarsening "
                         "levels', or use 'Method = fine'";
            message << "; the last converged state is kept";
            statistics.failure = message.str();
            // min_J describes the state kept, not the one rejected.
            statistics.min_J = accepted_min_J;
            pcout << "  Stopped: " << statistics.failure << std::endl;
            return statistics;
          }
        else
          {
            const double tried   = t_new - t;
            const bool   was_cut = steps.is_cut();
            if (!steps.cut())
              {
                std::ostringstream message;
                message << "the load increment at load factor " << t;
                if (was_cut)
                  message << " failed even when cut to " << tried;
                else
                  message << " failed, and no shorter one may follow";
                message << " (Nonlinear solver/Minimum load step = "
                        << parameters.minimum_step
                        << " of the nominal increment). Newton's method "
                           "stopped because "
                        << newton_failure
                        << ". The last converged state is kept";
                statistics.failure = message.str();
                pcout << "  Stopped: " << statistics.failure << std::endl;
                return statistics;
              }
            ++statistics.step_cuts;
            pcout << "  Cutting the load increment to " << steps.next() - t
                  << std::endl;
          }
      }
    statistics.converged = true;
    at_full_load         = true;
    return statistics;
  }



  bool
  StaticSolver::converge(const double    t,
                         Vector<double> &u,
                         Statistics     &statistics,
                         std::string    &inverted)
  {
    inverted.clear();
    if (!newton(t, u, statistics))
      return false;
    // A state that turns a cell inside out at a vertex solves the discrete
    // equations but is no deformation.
    const auto [vertex_J, vertex] = smallest_vertex_jacobian(u);
    if (!(vertex_J > 0))
      {
        std::ostringstream message;
        message << "turns the cell at " << format_point(vertex)
                << " m inside out at that corner of a solid voxel (det F = "
                << std::setprecision(3) << vertex_J
                << " there, positive at every quadrature point)";
        inverted = message.str();
        return false;
      }
    statistics.min_vertex_J = vertex_J;
    return true;
  }



  void
  StaticSolver::accept(Vector<double> &u,
                       const double    t,
                       Statistics     &statistics,
                       const std::function<void(unsigned int, double)> &on_step)
  {
    displacement.swap(u);
    ++statistics.load_steps;
    on_step(statistics.load_steps, t);
  }



  std::pair<double, Point<3>>
  StaticSolver::smallest_vertex_jacobian(const Vector<double> &u) const
  {
    // The corners of the block's w^3 voxels: the trapezoidal rule iterated
    // w times (the cell's vertices for a fine voxel).
    const unsigned int w = 1u << discretization.level;
    const QIterated<3> corners(QTrapezoid<1>(), w);
    // The solid voxels of a block (bits i + w (j + w k)) at each corner.
    std::vector<std::uint64_t> voxels_at(corners.size(), 0);
    for (unsigned int q = 0; q < corners.size(); ++q)
      for (unsigned int s = 0; s < 8; ++s)
        {
          std::array<int, 3> index;
          for (unsigned int d = 0; d < 3; ++d)
            index[d] = static_cast<int>(std::lround(corners.point(q)[d] * w)) -
                       static_cast<int>((s >> d) & 1);
          if (std::all_of(index.begin(), index.end(), [w](const int i) {
                return i >= 0 && i < static_cast<int>(w);
              }))
            voxels_at[q] |= std::uint64_t(1)
                            << (index[0] + w * (index[1] + w * index[2]));
        }
    FEValues<3>               fe_values(discretization.mapping,
                          discretization.fe,
                          corners,
                          update_gradients | update_quadrature_points);
    Vector<double>            local_u(discretization.fe.n_dofs_per_cell());
    std::vector<Tensor<2, 3>> F;
    FirstSmallest<Point<3>>   smallest;
    const auto reference = discretization.dof_handler.begin_active();
    for (const auto &cell : discretization.dof_handler.active_cell_iterators())
      {
        const Tensor<1, 3> shift =
          reinit_thread_independently(fe_values, cell, reference).shift;
        cell->get_dof_values(u, local_u);
        deformation_gradients(fe_values, local_u, F);
        const std::uint64_t solid =
          discretization.solid_voxels[cell->active_cell_index()];
        for (unsigned int q = 0; q < corners.size(); ++q)
          {
            if ((solid & voxels_at[q]) != 0)
              smallest.add(determinant(F[q]),
                           fe_values.quadrature_point(q) + shift);
          }
      }
    return {smallest.value(), smallest.place()};
  }



  StaticSolver::CellFields
  StaticSolver::cell_fields(const Vector<double> &u) const
  {
    const unsigned int n_cells = discretization.triangulation.n_active_cells();
    CellFields         fields{Vector<double>(n_cells),
                      Vector<double>(n_cells),
                      Vector<double>(n_cells)};
    FEValues<3>        fe_values(discretization.mapping,
                          discretization.fe,
                          discretization.quadrature,
                          update_gradients);
    Vector<double>     local_u(discretization.fe.n_dofs_per_cell());
    std::vector<Tensor<2, 3>> F;
    material::KernelResult    k;
    const auto reference = discretization.dof_handler.begin_active();
    for (const auto &cell : discretization.dof_handler.active_cell_iterators())
      {
        reinit_thread_independently(fe_values, cell, reference);
        cell->get_dof_values(u, local_u);
        deformation_gradients(fe_values, local_u, F);
        const unsigned int c = cell->active_cell_index();
        // The cells are boxes, so the rule's weights give the averages.
        for (unsigned int q = 0; q < F.size(); ++q)
          {
            const double w = discretization.quadrature.weight(q);
            fields.J(c) += w * determinant(F[q]);
            fields.strain(c) =
              std::max(fields.strain(c), material::principal_strain(F[q]));
            if (material::evaluate(F[q],
                                   discretization.material(c, q),
                                   material::KernelOutput::stress,
                                   k))
              fields.von_mises(c) +=
                w *
                material::von_mises(material::cauchy_stress(k.stress, F[q]));
          }
      }
    return fields;
  }



  Tensor<1, 3>
  StaticSolver::point_value(const Vector<double> &u, const Point<3> &p) const
  {
    return probe_displacement(discretization.mapping,
                              discretization.dof_handler,
                              u,
                              p);
  }



  Tensor<1, 3>
  probe_displacement(const Mapping<3>     &mapping,
                     const DoFHandler<3>  &dof_handler,
                     const Vector<double> &u,
                     const Point<3>       &p)
  {
    // The tolerance is in a cell's reference coordinates: twice the voxel
    // sizes that the scene's check of the probe allows (a coarse cell is 2
    // or 4 voxels wide), so that every model finds the points it accepts
    // whatever the round-off of either test. deal.II's default, 1e-10,
    // rejected a point 4e-10 voxel sizes off the solid in every model, and
    // one 1.5e-10 off in the fine model only.
    const auto cells = GridTools::find_all_active_cells_around_point(
      mapping, dof_handler, p, 2 * scene::probe_tolerance);
    AssertThrow(!cells.empty(), scene::probe_outside(p));
    Tensor<1, 3>                value;
    std::vector<Vector<double>> values(1, Vector<double>(3));
    for (const auto &[cell, unit_point] : cells)
      {
        FEValues<3> fe_values(mapping,
                              dof_handler.get_fe(),
                              Quadrature<3>(unit_point),
                              update_values);
        fe_values.reinit(cell);
        fe_values.get_function_values(u, values);
        for (unsigned int d = 0; d < 3; ++d)
          value[d] += values[0](d) / cells.size();
      }
    return value;
  }
} // namespace ddfem::solver
