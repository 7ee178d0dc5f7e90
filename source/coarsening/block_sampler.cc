#include <deal.II/base/geometry_info.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/mapping_q1.h>

#include <ddfem/coarsening/block_sampler.h>
#include <ddfem/scene/scene.h>
#include <ddfem/solver/cell_kernel.h>
#include <ddfem/solver/supports.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <set>

namespace ddfem::coarsening
{
  namespace
  {
    /// The orthonormal basis (modified Gram-Schmidt, twice, in order) of
    /// the span of @p rows; rows that depend on the earlier ones are
    /// dropped.
    FullMatrix<double>
    orthonormal_rows(const FullMatrix<double> &rows)
    {
      std::vector<Vector<double>> basis;
      for (unsigned int r = 0; r < rows.m(); ++r)
        {
          Vector<double> row(rows.n());
          for (unsigned int i = 0; i < rows.n(); ++i)
            row(i) = rows(r, i);
          const double length = row.l2_norm();
          // The second pass restores what round-off lost in the first.
          for (unsigned int pass = 0; pass < 2; ++pass)
            for (const Vector<double> &b : basis)
              row.add(-(row * b), b);
          if (row.l2_norm() > 1e-10 * length)
            basis.push_back(row /= row.l2_norm());
        }
      FullMatrix<double> result(basis.size(), rows.n());
      for (unsigned int r = 0; r < basis.size(); ++r)
        for (unsigned int i = 0; i < rows.n(); ++i)
          result(r, i) = basis[r](i);
      return result;
    }



    /// Removes from @p f its components along the orthonormal @p rows.
    void
    project_out(const FullMatrix<double> &rows, Vector<double> &f)
    {
      for (unsigned int r = 0; r < rows.m(); ++r)
        {
          double dot = 0;
          for (unsigned int i = 0; i < f.size(); ++i)
            dot += rows(r, i) * f(i);
          for (unsigned int i = 0; i < f.size(); ++i)
            f(i) -= dot * rows(r, i);
        }
    }



    /**
     * LU-factorizes @p A in place; returns false if it is exactly singular
     * (a zero pivot, which LAPACKFullMatrix throws as ExcSingular).
     */
    bool
    lu_factorize(LAPACKFullMatrix<double> &A)
    {
      try
        {
          A.compute_lu_factorization();
          return true;
        }
      catch (const LACExceptions::ExcSingular &)
        {
          return false;
        }
    }
  } // namespace



  void
  SamplingSettings::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Sampling");
    prm.declare_entry("Patterns",
                      "500",
                      Patterns::Integer(1, 20000),
                      "Number of random deformation patterns per 2x2x2 "
                      "block (the paper uses 500): self-equilibrated force "
                      "patterns on a free block, or embedded strains (see "
                      "Embedded fraction). At most 20000, and Patterns x "
                      "Magnitudes at most 100000 samples per block (40 times "
                      "the paper's: hours for a full database).");
    prm.declare_entry("Embedded fraction",
                      "1",
                      Patterns::Double(0, 1),
                      "Fraction of the patterns of a mixed block (its solid "
                      "voxels hold more than one material; with void voxels, "
                      "only a 2x2x2 block whose solid voxels are joined "
                      "through faces) that sample it as it deforms inside a "
                      "part: a random homogeneous strain that the block's "
                      "corners follow exactly and its other nodes up to a "
                      "periodic fluctuation (the block's homogenized "
                      "energy). The other patterns, and all patterns of "
                      "other blocks, are force patterns on a free block (the "
                      "paper's sampling, 0). Force patterns soften the stiff "
                      "children of mixed blocks; embedded samples of a "
                      "homogeneous block would equal the naive element. "
                      "doc/coarsening.md compares them.");
    prm.declare_entry("Magnitudes",
                      "5",
                      Patterns::Integer(1, 100),
                      "Number of magnitudes per pattern (the paper uses 5)."
                      " Each pattern gives this many samples.");
    prm.declare_entry("Minimum strain",
                      "0.02",
                      Patterns::Double(1e-6, 1),
                      "Linearized strain of the smallest magnitude: the "
                      "largest principal strain over the points of the "
                      "block's solid voxels of "
                      "its linear response to a force pattern, or of the "
                      "homogeneous strain of an embedded pattern (before its "
                      "relaxation, in which the soft children of a mixed "
                      "block strain more). "
                      "Magnitudes are scaled per block, so soft and stiff "
                      "blocks are sampled over the same strains. A build "
                      "prints the range of finite strains it sampled.");
    prm.declare_entry("Maximum strain",
                      "0.25",
                      Patterns::Double(1e-6, 1),
                      "Linearized strain of the largest magnitude.");
    prm.declare_entry("Magnitude spacing",
                      "even",
                      Patterns::Selection("even|geometric"),
                      "How the magnitudes between the smallest and the "
                      "largest are spread: 'even' (equal steps of strain) or "
                      "'geometric' (equal ratios, so more samples at small "
                      "strains, where most of a part's cells are). "
                      "doc/metamaterial_database.md measures both.");
    prm.declare_entry("Traction gradient",
                      "0.25",
                      Patterns::Double(0, 10),
                      "Force patterns are tractions sigma(x) n on the block's "
                      "surface from a random stress sigma0 + sum_d (2 x_d - 1) "
                      "sigma_d, all entries standard normal; this scales the "
                      "linear part. With 0.25 the stress varies by +-0.25 "
                      "sigma_d about its value at the block's center (by half "
                      "of sigma_d across the block), as in smooth fields two "
                      "voxels wide.");
    prm.declare_entry("Stretch directions",
                      "500",
                      Patterns::Integer(3, 20000),
                      "Number of stretching directions over the sphere used "
                      "to estimate the anisotropy directions (paper: 500).");
    prm.declare_entry("Seed",
                      "0",
                      Patterns::Integer(0, 1000000),
                      "Offsets the random generator of every block. Every "
                      "block has its own generator, so results do not depend "
                      "on threads; another seed draws other patterns, which "
                      "shows how much a result owes to the sampling noise "
                      "(doc/coarsening.md). Part of the database's settings.");
    prm.leave_subsection();
  }



  void
  SamplingSettings::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Sampling");
    n_directions         = prm.get_integer("Patterns");
    embedded             = prm.get_double("Embedded fraction");
    n_magnitudes         = prm.get_integer("Magnitudes");
    min_strain           = prm.get_double("Minimum strain");
    max_strain           = prm.get_double("Maximum strain");
    geometric_spacing    = prm.get("Magnitude spacing") == "geometric";
    traction_gradient    = prm.get_double("Traction gradient");
    n_stretch_directions = prm.get_integer("Stretch directions");
    seed                 = prm.get_integer("Seed");
    prm.leave_subsection();
    AssertThrow(min_strain <= max_strain,
                ExcMessage(
                  "Database/Sampling/Minimum strain (" +
                  std::to_string(min_strain) +
                  ") must not exceed Database/Sampling/Maximum strain (" +
                  std::to_string(max_strain) + ")."));
  }



  namespace
  {
    /// The groups of the solid children of a 2x2x2 block (@p solid[k]:
    /// whether child k, at octant (k & 1, (k >> 1) & 1, (k >> 2) & 1), is
    /// solid) that are joined through faces.
    solver::Components
    face_groups(const std::array<bool, 8> &solid)
    {
      solver::Components groups(8);
      for (unsigned int a = 0; a < 8; ++a)
        for (unsigned int d = 0; d < 3; ++d)
          if (solid[a] && solid[a ^ (1u << d)])
            groups.join(a, a ^ (1u << d));
      return groups;
    }



    /// Whether the solid voxels of the 2x2x2 block @p voxels form one
    /// group joined through faces.
    bool
    face_connected(const std::vector<scene::MaterialId> &voxels)
    {
      std::array<bool, 8> solid;
      for (unsigned int k = 0; k < 8; ++k)
        solid[k] = voxels[k] != scene::void_id;
      solver::Components         groups = face_groups(solid);
      std::optional<std::size_t> root;
      for (unsigned int k = 0; k < 8; ++k)
        if (solid[k])
          {
            if (root && *root != groups.find(k))
              return false;
            root = groups.find(k);
          }
      return true;
    }
  } // namespace



  SamplingSettings
  SamplingSettings::for_block(
    const std::vector<scene::MaterialId> &voxels) const
  {
    SamplingSettings result = *this;
    // Mixed: the solid voxels hold more than one material.
    std::optional<scene::MaterialId> material;
    bool                             mixed = false, has_void = false;
    for (const auto id : voxels)
      if (id == scene::void_id)
        has_void = true;
      else
        {
          mixed    = mixed || (material && *material != id);
          material = id;
        }
    // With void, only a 2x2x2 block whose solid voxels are joined through
    // their faces: children joined at an edge or a corner alone, each held
    // at its own corner, would relax to no energy. Embedded level-2 blocks
    // with void left a representative of the full database without a
    // sample.
    if (!mixed || (has_void && (voxels.size() != 8 || !face_connected(voxels))))
      result.embedded = 0;
    return result;
  }



  bool
  SamplingSettings::is_embedded(const unsigned int p) const
  {
    return std::floor((p + 1) * embedded) > std::floor(p * embedded);
  }



  unsigned int
  SamplingSettings::n_embedded() const
  {
    unsigned int n = 0;
    for (unsigned int p = 0; p < n_directions; ++p)
      n += is_embedded(p);
    return n;
  }



  BlockSampler::BlockSampler(
    const std::array<std::vector<material::MaterialPoint>, 8> &children,
    const double                     child_point_offset,
    const std::optional<VoidVoxels> &void_voxels)
    : materials(children)
    , void_octants(void_voxels.value_or(VoidVoxels{}))
    , fe(FE_Q<3>(1), 3)
  {
    scene::VoxelGrid grid({{2, 2, 2}}, 0.5);
    for (unsigned int k = 0; k < 8; ++k)
      {
        AssertThrow(children[k].empty() || children[k].size() == 8,
                    ExcMessage("A child of a sampled block needs its 8 "
                               "points' materials, or none (void)."));
        grid[k] = children[k].empty() ? scene::void_id : 1;
      }
    AssertThrow(grid.n_solid_voxels() > 0,
                ExcMessage("A block needs at least one solid child."));
    const std::vector<std::size_t> blocks =
      scene::make_voxel_mesh(grid, 0, triangulation);
    dof_handler.reinit(triangulation);
    dof_handler.distribute_dofs(fe);

    // All children are translates of one cube: one FEValues serves them.
    fe_values = std::make_unique<FEValues<3>>(
      fe,
      solver::coarse_quadrature(1, child_point_offset),
      update_gradients | update_JxW_values);
    fe_values->reinit(dof_handler.begin_active());
    dof_component = solver::dof_components(dof_handler);
    std::map<unsigned int, std::array<types::global_dof_index, 3>> vertices;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        cell_dofs.emplace_back(fe.n_dofs_per_cell());
        cell->get_dof_indices(cell_dofs.back());
        cell_child.push_back(blocks[cell->active_cell_index()]);
        for (const unsigned int v : cell->vertex_indices())
          for (unsigned int c = 0; c < 3; ++c)
            vertices[cell->vertex_index(v)][c] = cell->vertex_dof_index(v, c);
      }
    for (const auto &vertex : vertices)
      node_dofs.push_back(vertex.second);

    support_points.resize(dof_handler.n_dofs());
    DoFTools::map_dofs_to_support_points(MappingQ1<3>(),
                                         dof_handler,
                                         support_points);

    // Face-connected groups of children (octants).
    std::array<bool, 8> solid;
    for (unsigned int k = 0; k < 8; ++k)
      solid[k] = !children[k].empty();
    solver::Components                   groups = face_groups(solid);
    std::vector<std::vector<bool>>       group_dofs;
    std::map<unsigned int, unsigned int> group_number;
    for (unsigned int c = 0; c < cell_child.size(); ++c)
      {
        const unsigned int r = groups.find(cell_child[c]);
        if (group_number.count(r) == 0)
          {
            group_number[r] = group_dofs.size();
            group_dofs.emplace_back(dof_handler.n_dofs(), false);
          }
        for (const auto i : cell_dofs[c])
          group_dofs[group_number[r]][i] = true;
      }
    n_components = group_dofs.size();

    // The zero-energy modes of the block at rest: the motions that are
    // rigid on every group and agree on the nodes groups share, the six
    // rigid ones plus a hinge's relative rotations.
    const Point<3>                     center(0.5, 0.5, 0.5);
    std::vector<int>                   first_group(dof_handler.n_dofs(), -1);
    std::vector<std::array<double, 6>> rigid_modes;
    solver::RigidPartConditions        conditions(n_components, center, 1.);
    for (unsigned int i = 0; i < dof_handler.n_dofs(); ++i)
      {
        rigid_modes.push_back(
          solver::rigid_body_modes(support_points[i] - center,
                                   dof_component[i]));
        for (unsigned int g = 0; g < n_components; ++g)
          if (group_dofs[g][i])
            {
              if (first_group[i] < 0)
                first_group[i] = g;
              else
                conditions.join(support_points[i],
                                dof_component[i],
                                first_group[i],
                                g);
            }
      }
    const FullMatrix<double> null_space = conditions.free_motions();
    Assert(null_space.n() >= 6, ExcInternalError());
    constraints.reinit(null_space.n(), dof_handler.n_dofs());
    for (unsigned int r = 0; r < constraints.m(); ++r)
      for (unsigned int i = 0; i < dof_handler.n_dofs(); ++i)
        for (unsigned int m = 0; m < 6; ++m)
          constraints(r, i) +=
            rigid_modes[i][m] * null_space(6 * first_group[i] + m, r);
    constraints = orthonormal_rows(constraints);
    Assert(constraints.m() == null_space.n(), ExcInternalError());

    // Corners, and the trilinear least-squares fit for those whose voxel
    // is void: the fit of the field at the corners of the solid voxels
    // (the fine nodes), each the trilinear interpolation of its child's
    // nodes. Where the children are voxels, these are the nodes.
    std::map<unsigned int, unsigned int> node_of_vertex;
    for (const auto &vertex : vertices)
      node_of_vertex.emplace(vertex.first, node_of_vertex.size());
    const unsigned int voxels_per_edge = void_voxels ? 2 : 1;
    const double       h               = 0.5 / voxels_per_edge;
    // Per fine node (its coordinates in steps h), its interpolation.
    std::map<std::array<long, 3>, Vector<double>> fine_nodes;
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (unsigned int j = 0;
           j < voxels_per_edge * voxels_per_edge * voxels_per_edge;
           ++j)
        if (solid_octant(cell_child[cell->active_cell_index()], j))
          for (const unsigned int w : GeometryInfo<3>::vertex_indices())
            {
              Point<3>            x = cell->vertex(0);
              std::array<long, 3> key;
              for (unsigned int d = 0; d < 3; ++d)
                {
                  x[d] += h * (((j >> d) & 1) + ((w >> d) & 1));
                  key[d] = std::lround(x[d] / h);
                }
              Vector<double> &interpolation = fine_nodes[key];
              interpolation.reinit(node_dofs.size());
              for (const unsigned int v : cell->vertex_indices())
                interpolation(node_of_vertex.at(cell->vertex_index(v))) =
                  GeometryInfo<3>::d_linear_shape_function(
                    Point<3>((x - cell->vertex(0)) / 0.5), v);
            }
    FullMatrix<double> B(fine_nodes.size(), 8),
      P(fine_nodes.size(), node_dofs.size()), BtB(8, 8),
      BtP(8, node_dofs.size());
    unsigned int row = 0;
    for (const auto &[key, interpolation] : fine_nodes)
      {
        const Point<3> x(key[0] * h, key[1] * h, key[2] * h);
        for (unsigned int v = 0; v < 8; ++v)
          B(row, v) = GeometryInfo<3>::d_linear_shape_function(x, v);
        for (unsigned int n = 0; n < node_dofs.size(); ++n)
          P(row, n) = interpolation(n);
        ++row;
      }
    B.Tmmult(BtB, B);
    BtB.gauss_jordan();
    B.Tmmult(BtP, P);
    corner_weights.reinit(8, node_dofs.size());
    BtB.mmult(corner_weights, BtP);
    for (unsigned int v = 0; v < 8; ++v)
      {
        const Point<3> corner(v & 1, (v >> 1) & 1, (v >> 2) & 1);
        corner_dofs[v] = {{-1, -1, -1}};
        if (solid_octant(v, v))
          for (unsigned int i = 0; i < dof_handler.n_dofs(); ++i)
            if (support_points[i].distance(corner) < 1e-12)
              corner_dofs[v][dof_component[i]] = i;
      }

    // The quarters of the children's faces on the block's surface, those
    // of solid voxels (which force patterns load) and those of void ones.
    std::vector<SurfaceQuarter> void_quarters;
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int face : cell->face_indices())
        {
          const unsigned int d    = face / 2;
          const double       side = (face % 2 == 0) ? 0. : 1.;
          if (std::abs(cell->face(face)->center()[d] - side) > 1e-12)
            continue;
          Tensor<1, 3> normal;
          normal[d] = (face % 2 == 0) ? -1. : 1.;
          for (const unsigned int v : cell->face(face)->vertex_indices())
            {
              const Point<3> &x      = cell->face(face)->vertex(v);
              unsigned int    octant = 0;
              for (unsigned int e = 0; e < 3; ++e)
                if (x[e] > cell->center()[e])
                  octant |= 1u << e;
              (solid_octant(cell_child[cell->active_cell_index()], octant) ?
                 surface_quarters :
                 void_quarters)
                .push_back({x,
                            normal,
                            {{cell->face(face)->vertex_dof_index(v, 0),
                              cell->face(face)->vertex_dof_index(v, 1),
                              cell->face(face)->vertex_dof_index(v, 2)}}});
            }
        }
    // Sets load_constraints to the constraint rows on the loaded degrees of
    // freedom, orthonormalized (a force on these is self-equilibrated if
    // orthogonal to them), and returns the number of such forces' free
    // directions. Where the solid voxels' quarters leave none (none reaches
    // the block's surface, an island held inside it by its scene, or all
    // meet it at one node), all quarters are loaded; a solid child's own
    // faces always leave some.
    const auto restrict_constraints_to_loads = [this]() {
      std::set<types::global_dof_index> dofs;
      FullMatrix<double>                rows(constraints.m(), constraints.n());
      for (const SurfaceQuarter &quarter : surface_quarters)
        for (const auto i : quarter.dofs)
          {
            dofs.insert(i);
            for (unsigned int r = 0; r < constraints.m(); ++r)
              rows(r, i) = constraints(r, i);
          }
      load_constraints = orthonormal_rows(rows);
      return dofs.size() - load_constraints.m();
    };
    if (restrict_constraints_to_loads() == 0)
      {
        surface_quarters.insert(surface_quarters.end(),
                                void_quarters.begin(),
                                void_quarters.end());
        [[maybe_unused]] const auto n_free = restrict_constraints_to_loads();
        Assert(n_free > 0, ExcInternalError());
      }

    // Periodic classes of nodes (embedded samples): a node's class is the
    // set of its coordinates at mid-block, so opposite faces and edges
    // share one; corners (the empty set) follow the field exactly. A void
    // voxel leaves some nodes without a partner: the others of the class
    // share its fluctuation, and a node alone in its class moves freely.
    std::map<unsigned int, unsigned int> class_number;
    periodic_dof.assign(dof_handler.n_dofs(), -1);
    for (unsigned int i = 0; i < dof_handler.n_dofs(); ++i)
      {
        unsigned int key = 0;
        for (unsigned int d = 0; d < 3; ++d)
          if (std::abs(support_points[i][d] - 0.5) < 1e-12)
            key |= 1u << d;
        if (key == 0)
          continue;
        const auto inserted = class_number.emplace(key, class_number.size());
        periodic_dof[i]     = 3 * inserted.first->second + dof_component[i];
      }
    n_periodic = 3 * class_number.size();

    double             E;
    Vector<double>     r;
    FullMatrix<double> K;
    assemble(Vector<double>(dof_handler.n_dofs()), true, E, r, K);
    // Rigid motions are constrained and mechanisms hinged above.
    AssertThrow(factorize(K, initial_saddle), ExcInternalError());
  }



  bool
  BlockSampler::assemble(const Vector<double> &u,
                         const bool            tangent,
                         double               &energy,
                         Vector<double>       &residual,
                         FullMatrix<double>   &stiffness) const
  {
    const unsigned int n = dof_handler.n_dofs();
    energy               = 0;
    residual.reinit(n);
    if (tangent)
      stiffness.reinit(n, n);
    solver::CellContribution c;
    Vector<double>           local(fe.n_dofs_per_cell());
    for (unsigned int cell = 0; cell < cell_dofs.size(); ++cell)
      {
        const auto &dofs = cell_dofs[cell];
        for (unsigned int i = 0; i < dofs.size(); ++i)
          local(i) = u(dofs[i]);
        if (!solver::integrate_cell(*fe_values,
                                    local,
                                    materials[cell_child[cell]].data(),
                                    tangent ? material::KernelOutput::tangent :
                                              material::KernelOutput::stress,
                                    c))
          return false;
        energy += c.energy;
        for (unsigned int i = 0; i < dofs.size(); ++i)
          {
            residual(dofs[i]) += c.residual(i);
            if (tangent)
              for (unsigned int j = 0; j < dofs.size(); ++j)
                stiffness(dofs[i], dofs[j]) += c.tangent(i, j);
          }
      }
    return true;
  }



  bool
  BlockSampler::energy(const Vector<double> &u, double &energy) const
  {
    std::array<double, 8> energies;
    if (!child_energies(u, energies))
      return false;
    energy = std::accumulate(energies.begin(), energies.end(), 0.);
    return true;
  }



  bool
  BlockSampler::child_energies(const Vector<double>  &u,
                               std::array<double, 8> &energies) const
  {
    energies.fill(0.);
    solver::CellContribution c;
    Vector<double>           local(fe.n_dofs_per_cell());
    for (unsigned int cell = 0; cell < cell_dofs.size(); ++cell)
      {
        for (unsigned int i = 0; i < local.size(); ++i)
          local(i) = u(cell_dofs[cell][i]);
        if (!solver::integrate_cell(*fe_values,
                                    local,
                                    materials[cell_child[cell]].data(),
                                    material::KernelOutput::energy,
                                    c))
          return false;
        energies[cell_child[cell]] += c.energy;
      }
    return true;
  }



  bool
  BlockSampler::factorize(const FullMatrix<double> &K,
                          LAPACKFullMatrix<double> &A) const
  {
    const unsigned int n = K.m(), m = constraints.m();
    // Scale the constraint rows like the stiffness so LU pivots sensibly.
    double scale = 0;
    for (unsigned int i = 0; i < n; ++i)
      scale = std::max(scale, std::abs(K(i, i)));
    A.reinit(n + m);
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j)
        A(i, j) = K(i, j);
    for (unsigned int r = 0; r < m; ++r)
      for (unsigned int i = 0; i < n; ++i)
        {
          A(n + r, i) = scale * constraints(r, i);
          A(i, n + r) = scale * constraints(r, i);
        }
    return lu_factorize(A);
  }



  Vector<double>
  BlockSampler::constrained_solve(const LAPACKFullMatrix<double> &A,
                                  const Vector<double>           &b) const
  {
    Vector<double> x(A.m());
    for (unsigned int i = 0; i < b.size(); ++i)
      x(i) = b(i);
    A.solve(x);
    Vector<double> u(b.size());
    for (unsigned int i = 0; i < b.size(); ++i)
      u(i) = x(i);
    return u;
  }



  namespace
  {
    /**
     * The Newton steps solve() and relax() take at most; the state after
     * the last of them is checked for convergence too.
     */
    constexpr unsigned int max_newton_steps = 40;



    /**
     * Armijo backtracking: halves the step along @p dx from @p x until
     * @p merit (false where inadmissible) decreases by at least 1e-4 of
     * the linear prediction @p slope (negative) from @p merit0, and moves
     * @p x there. Returns false after 30 halvings.
     */
    bool
    backtrack(
      const std::function<bool(const Vector<double> &, double &)> &merit,
      const double                                                 merit0,
      const Vector<double>                                        &dx,
      const double                                                 slope,
      Vector<double>                                              &x)
    {
      double alpha = 1;
      for (unsigned int ls = 0; ls < 30; ++ls, alpha *= 0.5)
        {
          Vector<double> trial = x;
          trial.add(alpha, dx);
          double value;
          if (merit(trial, value) && value <= merit0 + 1e-4 * alpha * slope)
            {
              x = trial;
              return true;
            }
        }
      return false;
    }



    /**
     * The step a Newton iteration takes where the energy cannot resolve
     * the decrease (near convergence its terms cancel to second order in
     * the strain, the more so at a high stiffness contrast): the full step
     * along @p dx from @p x, if it reduces the residual norm from
     * @p residual0 (@p residual_norm: false where inadmissible). Moves
     * @p x and returns true if so.
     */
    bool
    take_full_step_if_residual_falls(
      const std::function<bool(const Vector<double> &, double &)>
                           &residual_norm,
      const double          residual0,
      const Vector<double> &dx,
      Vector<double>       &x)
    {
      Vector<double> trial = x;
      trial += dx;
      double residual;
      if (!residual_norm(trial, residual) || !(residual < residual0))
        return false;
      x = trial;
      return true;
    }
  } // namespace



  bool
  BlockSampler::solve(const Vector<double> &f, Vector<double> &u) const
  {
    const double             f_norm = f.l2_norm();
    double                   E;
    Vector<double>           r;
    FullMatrix<double>       K;
    LAPACKFullMatrix<double> A;
    for (unsigned int it = 0;; ++it)
      {
        if (!assemble(u, true, E, r, K))
          return false;
        Vector<double> g = f;
        g -= r;
        Vector<double> projected = g;
        project_out(constraints, projected);
        const double residual = projected.l2_norm() / f_norm;
        if (residual <= 1e-9)
          return true;
        if (it == max_newton_steps)
          return false;

        // An exactly singular tangent gives no direction: the sample is
        // dropped, as where Newton fails.
        if (!factorize(K, A))
          return false;
        const Vector<double> du    = constrained_solve(A, g);
        const double         slope = -(g * du);
        // A step at round-off level: converged if the residual is small.
        if (du.l2_norm() <= 1e-12 * u.l2_norm() || !(slope < 0))
          return residual <= 1e-6;
        // At round-off level the energy cannot resolve the decrease.
        if (-slope < 1e-10 * std::abs(E))
          {
            const auto projected_norm = [&](const Vector<double> &v,
                                            double               &norm) {
              double             unused_energy;
              Vector<double>     trial_residual;
              FullMatrix<double> unused;
              if (!assemble(v, false, unused_energy, trial_residual, unused))
                return false;
              trial_residual.sadd(-1., 1., f);
              project_out(constraints, trial_residual);
              norm = trial_residual.l2_norm();
              return true;
            };
            if (!take_full_step_if_residual_falls(
                  projected_norm, projected.l2_norm(), du, u))
              return residual <= 1e-6;
            continue;
          }

        const auto potential = [&](const Vector<double> &v, double &value) {
          if (!energy(v, value))
            return false;
          value -= f * v;
          return true;
        };
        if (!backtrack(potential, E - f * u, du, slope, u))
          return residual <= 1e-6;
      }
  }



  Vector<double>
  BlockSampler::add_fluctuation(const Vector<double> &u_base,
                                const Vector<double> &w) const
  {
    Vector<double> u = u_base;
    for (unsigned int i = 0; i < u.size(); ++i)
      if (periodic_dof[i] >= 0)
        u(i) += w(periodic_dof[i]);
    return u;
  }



  bool
  BlockSampler::relax(const Vector<double> &u_base, Vector<double> &w) const
  {
    // Energy, gradient g and (if H is given) Hessian with respect to the
    // fluctuation v, gathered over the periodic classes, and the norm of
    // all nodal forces (the scale of g).
    Vector<double>     r;
    FullMatrix<double> K;
    const auto         gather = [&](const Vector<double>     &v,
                            double                   &E,
                            Vector<double>           &g,
                            LAPACKFullMatrix<double> *H,
                            double                   &force_norm) {
      if (!assemble(add_fluctuation(u_base, v), H != nullptr, E, r, K))
        return false;
      g.reinit(n_periodic);
      for (unsigned int i = 0; i < r.size(); ++i)
        if (periodic_dof[i] >= 0)
          {
            g(periodic_dof[i]) += r(i);
            if (H != nullptr)
              for (unsigned int j = 0; j < r.size(); ++j)
                if (periodic_dof[j] >= 0)
                  (*H)(periodic_dof[i], periodic_dof[j]) += K(i, j);
          }
      force_norm = r.l2_norm();
      return true;
    };

    for (unsigned int it = 0;; ++it)
      {
        double                   E, force_norm;
        Vector<double>           g;
        LAPACKFullMatrix<double> H(n_periodic);
        if (!gather(w, E, g, &H, force_norm))
          return false;
        // Converged when the unbalanced forces are negligible against the
        // forces on the prescribed nodes, or there are no forces at all.
        const double residual = g.l2_norm() / force_norm;
        if (force_norm == 0 || residual <= 1e-9)
          return true;
        if (it == max_newton_steps)
          return false;

        // Newton's direction; where the Hessian is indefinite (the soft
        // children buckle under compression), shift it until it descends.
        // The shifts scale with the largest diagonal entry, or with the
        // largest in magnitude where none is positive (a shift of 0 would
        // be doubled forever).
        double largest = 0;
        for (unsigned int i = 0; i < n_periodic; ++i)
          largest = std::max(largest, H(i, i));
        if (!(largest > 0))
          for (unsigned int i = 0; i < n_periodic; ++i)
            largest = std::max(largest, std::abs(H(i, i)));
        if (!(largest > 0))
          return residual <= 1e-6;
        Vector<double> dw;
        double         slope = 0;
        for (double shift = 0;;)
          {
            LAPACKFullMatrix<double> A = H;
            for (unsigned int i = 0; i < n_periodic; ++i)
              A(i, i) += shift;
            // An exactly singular shifted Hessian does not descend either.
            const bool regular = lu_factorize(A);
            dw                 = g;
            if (regular)
              A.solve(dw);
            dw *= -1.;
            slope = regular ? g * dw : 0.;
            if (slope < 0 || shift > 1e3 * largest)
              break;
            shift = std::max(2 * shift, 1e-3 * largest);
          }
        if (!(slope < 0))
          return residual <= 1e-6;

        // At round-off level, or where the line search fails there, the
        // full step if it reduces the unbalanced forces.
        const auto relaxed = [&](const Vector<double> &v, double &value) {
          return energy(add_fluctuation(u_base, v), value);
        };
        const auto unbalanced = [&](const Vector<double> &v, double &norm) {
          Vector<double> trial_g;
          double         unused_energy, unused_norm;
          if (!gather(v, unused_energy, trial_g, nullptr, unused_norm))
            return false;
          norm = trial_g.l2_norm();
          return true;
        };
        if ((-slope < 1e-10 * std::abs(E) ||
             !backtrack(relaxed, E, dw, slope, w)) &&
            !take_full_step_if_residual_falls(unbalanced, g.l2_norm(), dw, w))
          return residual <= 1e-6;
      }
  }



  double
  BlockSampler::largest_over_points(
    const Vector<double>                              &u,
    const std::function<double(const Tensor<2, 3> &)> &measure) const
  {
    double                    largest = 0;
    Vector<double>            local(fe.n_dofs_per_cell());
    std::vector<Tensor<2, 3>> F;
    for (unsigned int cell = 0; cell < cell_dofs.size(); ++cell)
      {
        for (unsigned int i = 0; i < local.size(); ++i)
          local(i) = u(cell_dofs[cell][i]);
        solver::deformation_gradients(*fe_values, local, F);
        for (unsigned int q = 0; q < F.size(); ++q)
          if (solid_octant(cell_child[cell], q))
            largest = std::max(largest, measure(F[q]));
      }
    return largest;
  }



  double
  BlockSampler::linearized_strain(const Vector<double> &u) const
  {
    return largest_over_points(u, material::linearized_strain);
  }



  double
  BlockSampler::finite_strain(const Vector<double> &u) const
  {
    return largest_over_points(u, material::principal_strain);
  }



  CornerDisplacements
  BlockSampler::corners(const Vector<double> &u) const
  {
    CornerDisplacements result;
    for (unsigned int v = 0; v < 8; ++v)
      for (unsigned int c = 0; c < 3; ++c)
        {
          if (corner_dofs[v][c] >= 0)
            result[v][c] = u(corner_dofs[v][c]);
          else
            {
              for (unsigned int n = 0; n < node_dofs.size(); ++n)
                result[v][c] += corner_weights(v, n) * u(node_dofs[n][c]);
            }
        }
    return result;
  }



  Vector<double>
  BlockSampler::boundary_forces(
    const std::function<Tensor<2, 3>(const Point<3> &)> &stress) const
  {
    Vector<double> f(dof_handler.n_dofs());
    for (const SurfaceQuarter &quarter : surface_quarters)
      {
        // Lumped: a quarter of the child face's area per vertex.
        const Tensor<1, 3> t =
          stress(quarter.vertex) * quarter.normal * (0.25 / 4);
        for (unsigned int i = 0; i < 3; ++i)
          f(quarter.dofs[i]) += t[i];
      }
    const double traction = f.l2_norm();
    project_out(load_constraints, f);
    // What is left at round-off is no force.
    if (f.l2_norm() <= 1e-12 * traction)
      f = 0;
    return f;
  }



  Vector<double>
  BlockSampler::interpolate(
    const std::function<Tensor<1, 3>(const Point<3> &)> &u) const
  {
    Vector<double> result(dof_handler.n_dofs());
    for (unsigned int i = 0; i < result.size(); ++i)
      result(i) = u(support_points[i])[dof_component[i]];
    return result;
  }



  Vector<double>
  BlockSampler::homogeneous_strain(const Tensor<2, 3> &H) const
  {
    const Point<3> center(0.5, 0.5, 0.5);
    return interpolate([&](const Point<3> &x) { return H * (x - center); });
  }



  namespace
  {
    /// The linearized strain of magnitude @p j of a pattern (see sample()).
    double
    target_strain(const SamplingSettings &settings, const unsigned int j)
    {
      if (settings.n_magnitudes == 1)
        return settings.max_strain;
      const double t = double(j) / (settings.n_magnitudes - 1);
      return settings.geometric_spacing ?
               settings.min_strain *
                 std::pow(settings.max_strain / settings.min_strain, t) :
               settings.min_strain +
                 (settings.max_strain - settings.min_strain) * t;
    }
  } // namespace



  std::vector<Sample>
  BlockSampler::sample(const SamplingSettings &settings,
                       const std::uint64_t     seed,
                       unsigned int           &n_dropped) const
  {
    std::mt19937_64                  generator(seed);
    std::normal_distribution<double> distribution;
    const std::function<double()>    normal = [&]() {
      return distribution(generator);
    };
    std::vector<Sample> samples;
    n_dropped = 0;
    // The samples are labelled with their pattern's index among the
    // patterns of its kind, so that a held-out split (every n-th label)
    // takes force and embedded patterns alike. With the pattern's own
    // index, every held-out pattern was embedded for an embedded fraction
    // of 0.2 and Held-out every = 5, and the fit saw force patterns only.
    unsigned int n_embedded = 0;
    for (unsigned int p = 0; p < settings.n_directions; ++p)
      if (settings.is_embedded(p))
        embedded_pattern(settings, n_embedded++, normal, samples, n_dropped);
      else
        force_pattern(settings, p - n_embedded, normal, samples, n_dropped);
    return samples;
  }



  void
  BlockSampler::force_pattern(const SamplingSettings        &settings,
                              const unsigned int             p,
                              const std::function<double()> &normal,
                              std::vector<Sample>           &samples,
                              unsigned int                  &n_dropped) const
  {
    Tensor<2, 3>                constant;
    std::array<Tensor<2, 3>, 3> gradient;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = i; j < 3; ++j)
        {
          constant[i][j] = constant[j][i] = normal();
          for (unsigned int d = 0; d < 3; ++d)
            gradient[d][i][j] = gradient[d][j][i] = normal();
        }
    Vector<double> f = boundary_forces([&](const Point<3> &x) {
      Tensor<2, 3> sigma = constant;
      for (unsigned int d = 0; d < 3; ++d)
        sigma += settings.traction_gradient * (2 * x[d] - 1) * gradient[d];
      return sigma;
    });
    if (f.l2_norm() == 0)
      {
        n_dropped += settings.n_magnitudes;
        return;
      }
    f /= f.l2_norm();
    const Vector<double> linear   = constrained_solve(initial_saddle, f);
    const double         strain_1 = linearized_strain(linear);

    Vector<double> u(dof_handler.n_dofs());
    double         previous = 0;
    for (unsigned int j = 0; j < settings.n_magnitudes; ++j)
      {
        const double magnitude = target_strain(settings, j) / strain_1;
        // Predictor: the linear response for the first magnitude, the
        // previous solution scaled for the others.
        Vector<double> guess = u;
        if (previous == 0)
          guess.add(magnitude, linear);
        else
          guess *= magnitude / previous;
        double e;
        if (!energy(guess, e))
          guess = u;
        Vector<double> force = f;
        force *= magnitude;
        if (!solve(force, guess))
          {
            n_dropped += settings.n_magnitudes - j;
            return;
          }
        u        = guess;
        previous = magnitude;
        samples.push_back(sample_of(u, p));
      }
  }



  void
  BlockSampler::embedded_pattern(const SamplingSettings        &settings,
                                 const unsigned int             p,
                                 const std::function<double()> &normal,
                                 std::vector<Sample>           &samples,
                                 unsigned int                  &n_dropped) const
  {
    Tensor<2, 3> H;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = i; j < 3; ++j)
        H[i][j] = H[j][i] = normal();
    const Vector<double> linear   = homogeneous_strain(H);
    const double         strain_1 = linearized_strain(linear);

    Vector<double> w(n_periodic);
    double         previous = 0;
    for (unsigned int j = 0; j < settings.n_magnitudes; ++j)
      {
        const double   magnitude = target_strain(settings, j) / strain_1;
        Vector<double> u_base    = linear;
        u_base *= magnitude;
        // Predictor: the previous fluctuation scaled.
        Vector<double> guess = w;
        if (previous > 0)
          guess *= magnitude / previous;
        double e;
        if (!energy(add_fluctuation(u_base, guess), e))
          guess = w;
        if (!relax(u_base, guess))
          {
            n_dropped += settings.n_magnitudes - j;
            return;
          }
        w        = guess;
        previous = magnitude;
        // The corners keep the field's values: they do not relax.
        samples.push_back(sample_of(add_fluctuation(u_base, w), p));
      }
  }



  Sample
  BlockSampler::sample_of(const Vector<double> &u, const unsigned int p) const
  {
    Sample s;
    s.corners = corners(u);
    energy(u, s.energy);
    s.strain  = finite_strain(u);
    s.pattern = p;
    return s;
  }



  namespace
  {
    /// Direction @p s of @p n Fibonacci points on the unit sphere.
    Tensor<1, 3>
    sphere_direction(const unsigned int s, const unsigned int n)
    {
      const double z   = 1. - (2. * s + 1.) / n;
      const double rho = std::sqrt(std::max(0., 1. - z * z));
      const double phi = s * numbers::PI * (3. - std::sqrt(5.));
      Tensor<1, 3> d;
      d[0] = rho * std::cos(phi);
      d[1] = rho * std::sin(phi);
      d[2] = z;
      return d;
    }
  } // namespace



  std::vector<Tensor<1, 3>>
  BlockSampler::anisotropy_directions(const SamplingSettings &settings,
                                      const CoarseElement    &element) const
  {
    // As in sample(): not embedded where the fraction of embedded patterns
    // rounds down to none.
    return settings.n_embedded() > 0 ?
             embedded_stretch_directions(settings, element) :
             free_stretch_directions(settings, element);
  }



  std::vector<Tensor<1, 3>>
  BlockSampler::free_stretch_directions(const SamplingSettings &settings,
                                        const CoarseElement    &element) const
  {
    // The same stress in every direction (paper 4.3: the block stretches
    // least along its stiff directions), scaled once so that the largest
    // strain of any direction is 0.01.
    const unsigned int n_d = settings.n_stretch_directions;
    std::vector<std::pair<Tensor<1, 3>, Vector<double>>> responses;
    double                                               largest_strain = 0;
    for (unsigned int s = 0; s < n_d; ++s)
      {
        const Tensor<1, 3> d = sphere_direction(s, n_d);
        Vector<double>     f = boundary_forces(
          [&d](const Point<3> &) { return outer_product(d, d); });
        // A stress whose traction on the loaded faces is its resultant
        // force and moment alone stretches nothing once they are removed.
        if (f.l2_norm() == 0)
          continue;
        responses.emplace_back(d, constrained_solve(initial_saddle, f));
        largest_strain =
          std::max(largest_strain, linearized_strain(responses.back().second));
      }
    const unsigned int                 n_points = element.n_points();
    std::vector<SymmetricTensor<2, 3>> M(n_points);
    std::vector<Tensor<2, 3>>          F;
    for (auto &[d, u] : responses)
      {
        u *= 0.01 / largest_strain;
        element.deformation_gradients(corners(u), F);
        for (unsigned int q = 0; q < n_points; ++q)
          {
            const double l = (F[q] * d).norm() - 1.;
            M[q] += l * l * symmetrize(outer_product(d, d));
          }
      }
    std::vector<Tensor<1, 3>> directions(n_points);
    for (unsigned int q = 0; q < n_points; ++q)
      directions[q] = eigenvectors(M[q])[2].second; // least stretch
    return directions;
  }



  std::vector<Tensor<1, 3>>
  BlockSampler::embedded_stretch_directions(const SamplingSettings &settings,
                                            const CoarseElement &element) const
  {
    // The relaxed response is linear in the strain at small strains: relax
    // the six unit strains once, and superpose them for every direction.
    // Should a relaxation fail, the free block's test still gives
    // directions.
    const double                  strain = 1e-3;
    std::array<Vector<double>, 6> unit_fields;
    for (unsigned int c = 0, i = 0; i < 3; ++i)
      for (unsigned int j = i; j < 3; ++j, ++c)
        {
          Tensor<2, 3> H;
          H[i][j]                     = strain;
          H[j][i]                     = strain;
          const Vector<double> u_base = homogeneous_strain(H);
          Vector<double>       w(n_periodic);
          if (!relax(u_base, w))
            return free_stretch_directions(settings, element);
          unit_fields[c] = add_fluctuation(u_base, w);
        }

    std::array<SymmetricTensor<2, 3>, 8> M;
    const unsigned int                   n_d = settings.n_stretch_directions;
    std::array<double, 8>                energies;
    for (unsigned int s = 0; s < n_d; ++s)
      {
        const Tensor<1, 3> d = sphere_direction(s, n_d);
        Vector<double>     u(unit_fields[0].size());
        for (unsigned int c = 0, i = 0; i < 3; ++i)
          for (unsigned int j = i; j < 3; ++j, ++c)
            u.add(d[i] * d[j], unit_fields[c]);
        if (!child_energies(u, energies))
          return free_stretch_directions(settings, element);
        const SymmetricTensor<2, 3> dd = symmetrize(outer_product(d, d));
        for (unsigned int k = 0; k < 8; ++k)
          M[k] += energies[k] * dd;
      }
    std::vector<Tensor<1, 3>> directions(element.n_points());
    for (unsigned int q = 0; q < element.n_points(); ++q)
      directions[q] = // the largest energy
        eigenvectors(M[element.child_of_point(q)])[0].second;
    return directions;
  }
} // namespace ddfem::coarsening
