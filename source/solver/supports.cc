#include <deal.II/base/exceptions.h>
#include <deal.II/fe/fe.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <SuiteSparseQR_C.h>
#include <ddfem/base/parsing.h>
#include <ddfem/solver/supports.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <numeric>
#include <set>

namespace ddfem::solver
{
  Components::Components(const std::size_t n)
    : parent(n)
  {
    std::iota(parent.begin(), parent.end(), 0);
  }



  std::size_t
  Components::find(std::size_t i)
  {
    while (parent[i] != i)
      i = parent[i] = parent[parent[i]];
    return i;
  }



  void
  Components::join(const std::size_t a, const std::size_t b)
  {
    parent[find(a)] = find(b);
  }



  Components
  vertex_connected_parts(const Triangulation<3> &tria)
  {
    Components                parts(tria.n_active_cells());
    std::vector<unsigned int> first_cell_at_vertex(
      tria.n_vertices(), numbers::invalid_unsigned_int);
    for (const auto &cell : tria.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        {
          unsigned int &first = first_cell_at_vertex[cell->vertex_index(v)];
          if (first == numbers::invalid_unsigned_int)
            first = cell->active_cell_index();
          else
            parts.join(cell->active_cell_index(), first);
        }
    return parts;
  }



  Components
  face_connected_parts(const Triangulation<3> &tria)
  {
    Components parts(tria.n_active_cells());
    for (const auto &cell : tria.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        // A neighbor with children across a hanging face has no active
        // cell index; its children join from their side.
        if (!cell->at_boundary(f) && cell->neighbor(f)->is_active())
          parts.join(cell->active_cell_index(),
                     cell->neighbor(f)->active_cell_index());
    return parts;
  }



  std::array<double, 6>
  rigid_body_modes(const Tensor<1, 3> &r, const unsigned int component)
  {
    std::array<double, 6> m = {};
    m[component]            = 1;
    for (unsigned int k = 0; k < 3; ++k)
      {
        Tensor<1, 3> e;
        e[k]     = 1;
        m[3 + k] = cross_product_3d(e, r)[component];
      }
    return m;
  }



  RigidPartConditions::RigidPartConditions(const unsigned int n_parts,
                                           const Point<3>    &center,
                                           const double       scale)
    : n_parts(n_parts)
    , center(center)
    , scale(scale)
  {}



  void
  RigidPartConditions::join(const Point<3>    &x,
                            const unsigned int component,
                            const unsigned int a,
                            const unsigned int b)
  {
    add_condition(x, component, {{a, 1.}, {b, -1.}});
  }



  void
  RigidPartConditions::hold(const Point<3>    &x,
                            const unsigned int component,
                            const unsigned int a)
  {
    add_condition(x, component, {{a, 1.}});
  }



  void
  RigidPartConditions::add_condition(
    const Point<3>                                              &x,
    const unsigned int                                           component,
    const std::initializer_list<std::pair<unsigned int, double>> parts)
  {
    const std::array<double, 6> modes =
      rigid_body_modes((x - center) / scale, component);
    std::vector<std::pair<unsigned int, double>> row;
    for (const auto &[p, sign] : parts)
      {
        AssertIndexRange(p, n_parts);
        for (unsigned int i = 0; i < 6; ++i)
          if (modes[i] != 0)
            row.emplace_back(6 * p + i, sign * modes[i]);
      }
    conditions.push_back(std::move(row));
  }



  FullMatrix<double>
  RigidPartConditions::free_motions() const
  {
    LAPACKFullMatrix<double> gram(6 * n_parts);
    for (const auto &row : conditions)
      for (const auto &[i, c_i] : row)
        for (const auto &[j, c_j] : row)
          gram(i, j) += c_i * c_j;
    Vector<double>     eigenvalues;
    FullMatrix<double> motions;
    gram.compute_eigenvalues_symmetric(-1., 1e-8, 0., eigenvalues, motions);
    return motions;
  }



  unsigned int
  RigidPartConditions::n_free_motions() const
  {
    const unsigned int n_unknowns = 6 * n_parts;
    std::size_t        n_entries  = 0;
    for (const auto &row : conditions)
      n_entries += row.size();
    if (n_entries == 0)
      return n_unknowns;

    cholmod_common common;
    cholmod_l_start(&common);
    common.print             = 0;
    cholmod_triplet *triplet = cholmod_l_allocate_triplet(
      conditions.size(), n_unknowns, n_entries, 0, CHOLMOD_REAL, &common);
    SuiteSparse_long rank = -1;
    if (triplet != nullptr)
      {
        auto *const rows    = static_cast<SuiteSparse_long *>(triplet->i);
        auto *const columns = static_cast<SuiteSparse_long *>(triplet->j);
        auto *const values  = static_cast<double *>(triplet->x);
        for (std::size_t r = 0; r < conditions.size(); ++r)
          for (const auto &[column, value] : conditions[r])
            {
              rows[triplet->nnz]     = r;
              columns[triplet->nnz]  = column;
              values[triplet->nnz++] = value;
            }
        cholmod_sparse *matrix =
          cholmod_l_triplet_to_sparse(triplet, n_entries, &common);
        cholmod_l_free_triplet(&triplet, &common);
        if (matrix != nullptr)
          {
            rank = SuiteSparseQR_C(SPQR_ORDERING_DEFAULT,
                                   SPQR_DEFAULT_TOL,
                                   0,
                                   0,
                                   matrix,
                                   nullptr,
                                   nullptr,
                                   nullptr,
                                   nullptr,
                                   nullptr,
                                   nullptr,
                                   nullptr,
                                   nullptr,
                                   nullptr,
                                   &common);
            cholmod_l_free_sparse(&matrix, &common);
          }
      }
    const int status = common.status;
    cholmod_l_finish(&common);
    if (rank < 0 && status == CHOLMOD_OUT_OF_MEMORY)
      throw std::bad_alloc();
    AssertThrow(rank >= 0,
                ExcMessage("SuiteSparseQR could not factorize the " +
                           std::to_string(conditions.size()) + " x " +
                           std::to_string(n_unknowns) +
                           " matrix of the conditions on the rigid motions "
                           "of " +
                           std::to_string(n_parts) +
                           " parts that share only edges or corners "
                           "(CHOLMOD status " +
                           std::to_string(status) + ")."));
    return n_unknowns - static_cast<unsigned int>(rank);
  }



  std::vector<unsigned int>
  dof_components(const DoFHandler<3> &dof_handler)
  {
    const FiniteElement<3>              &fe = dof_handler.get_fe();
    std::vector<unsigned int>            component(dof_handler.n_dofs());
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        cell->get_dof_indices(dofs);
        for (unsigned int i = 0; i < dofs.size(); ++i)
          component[dofs[i]] = fe.system_to_component_index(i).first;
      }
    return component;
  }



  unsigned int
  fixed_rigid_modes(const std::vector<ConstrainedRow> &rows)
  {
    if (rows.empty())
      return 0;
    Point<3> centroid;
    for (const auto &row : rows)
      centroid += row.first / static_cast<double>(rows.size());
    double scale = 0;
    for (const auto &row : rows)
      scale = std::max(scale, row.first.distance(centroid));
    scale = (scale > 0 ? scale : 1);

    double gram[6][6] = {};
    for (const auto &row : rows)
      {
        const std::array<double, 6> m =
          rigid_body_modes((row.first - centroid) / scale, row.second);
        for (unsigned int a = 0; a < 6; ++a)
          for (unsigned int b = 0; b < 6; ++b)
            gram[a][b] += m[a] * m[b];
      }
    // Scaled to a unit diagonal: a mode held by a few rows (a turn about
    // the normal of a plate held across its whole face, stopped at two
    // neighbouring nodes) has a diagonal entry that does not grow with the
    // rows holding the others, and would otherwise fall below the
    // tolerance of a large part. A mode no row holds keeps its 0.
    double diagonal[6];
    for (unsigned int a = 0; a < 6; ++a)
      diagonal[a] = std::sqrt(gram[a][a]);
    for (unsigned int a = 0; a < 6; ++a)
      for (unsigned int b = 0; b < 6; ++b)
        if (diagonal[a] > 0 && diagonal[b] > 0)
          gram[a][b] /= diagonal[a] * diagonal[b];
    // Gaussian elimination with full pivoting; the rank is the number of
    // pivots above a relative tolerance.
    double       max_pivot   = 0;
    unsigned int rank        = 0;
    bool         used_row[6] = {}, used_col[6] = {};
    for (unsigned int step = 0; step < 6; ++step)
      {
        double       best = 0;
        unsigned int pr = 0, pc = 0;
        for (unsigned int a = 0; a < 6; ++a)
          for (unsigned int b = 0; b < 6; ++b)
            if (!used_row[a] && !used_col[b] && std::abs(gram[a][b]) > best)
              best = std::abs(gram[a][b]), pr = a, pc = b;
        max_pivot = std::max(max_pivot, best);
        if (best <= 1e-10 * max_pivot || best == 0)
          break;
        ++rank;
        used_row[pr] = used_col[pc] = true;
        for (unsigned int a = 0; a < 6; ++a)
          if (!used_row[a])
            {
              const double f = gram[a][pc] / gram[pr][pc];
              for (unsigned int b = 0; b < 6; ++b)
                gram[a][b] -= f * gram[pr][b];
            }
      }
    return rank;
  }



  void
  require_supported_parts(
    const Triangulation<3>                                   &tria,
    Components                                               &parts,
    const std::map<std::size_t, std::vector<ConstrainedRow>> &rows,
    const std::string                                        &shared)
  {
    AssertThrow(
      std::any_of(rows.begin(),
                  rows.end(),
                  [](const auto &part_rows) {
                    return !part_rows.second.empty();
                  }),
      ExcMessage(
        "No Dirichlet condition (fixed, sliding, displacement or "
        "rotation) acts on any node of the solid, so rigid body "
        "motions are not prevented. Add one in 'Boundary conditions'."));
    std::set<std::size_t> representatives;
    for (unsigned int c = 0; c < tria.n_active_cells(); ++c)
      representatives.insert(parts.find(c));
    for (const std::size_t part : representatives)
      {
        const auto         r = rows.find(part);
        const unsigned int fixed =
          r == rows.end() ? 0 : fixed_rigid_modes(r->second);
        if (fixed == 6)
          continue;
        AssertThrow(
          representatives.size() > 1,
          ExcMessage(
            "The Dirichlet conditions leave " + std::to_string(6 - fixed) +
            " of the 6 rigid body motions of the solid free (a lone "
            "'sliding' floor, for example, allows sliding and spinning "
            "in its plane). Add conditions in 'Boundary conditions'."));
        unsigned int cells = 0;
        Point<3>     where;
        for (const auto &cell : tria.active_cell_iterators())
          if (parts.find(cell->active_cell_index()) == part && cells++ == 0)
            where = cell->center();
        AssertThrow(
          false,
          ExcMessage(
            std::to_string(cells) + " voxel(s) around " + format_point(where) +
            " m share no " + shared + " with the other parts, and " +
            (fixed == 0 ?
               "no Dirichlet condition acts on them: they float "
               "free. Connect them to a held part, hold them in "
               "'Boundary conditions', or remove them." :
               "their Dirichlet conditions fix only " + std::to_string(fixed) +
                 " of their 6 rigid body motions. Add conditions "
                 "in 'Boundary conditions', or connect them to a "
                 "held part.")));
      }
  }



  void
  require_supported_mesh(
    const Triangulation<3>                         &tria,
    const std::vector<std::vector<ConstrainedRow>> &cell_rows)
  {
    // Parts sharing nodes (vertex-connected cells) and parts sharing faces.
    Components by_vertex = vertex_connected_parts(tria);
    Components by_face   = face_connected_parts(tria);

    // Constrained rows per part; per face-connected part its cells, the
    // center of its first cell and its extent; per vertex the
    // face-connected parts touching it.
    std::map<std::size_t, std::vector<ConstrainedRow>> vertex_rows, face_rows;
    struct Part
    {
      unsigned int cells = 0;
      Point<3>     first_center;
      Point<3>     lower, upper;
    };
    std::map<std::size_t, Part>        face_parts;
    std::vector<std::set<std::size_t>> parts_at_vertex(tria.n_vertices());
    for (const auto &cell : tria.active_cell_iterators())
      {
        const unsigned int c  = cell->active_cell_index();
        const std::size_t  pv = by_vertex.find(c), pf = by_face.find(c);
        Part              &part = face_parts[pf];
        if (part.cells++ == 0)
          part.first_center = part.lower = part.upper = cell->center();
        for (const unsigned int v : cell->vertex_indices())
          {
            parts_at_vertex[cell->vertex_index(v)].insert(pf);
            for (unsigned int d = 0; d < 3; ++d)
              {
                part.lower[d] = std::min(part.lower[d], cell->vertex(v)[d]);
                part.upper[d] = std::max(part.upper[d], cell->vertex(v)[d]);
              }
          }
        for (const ConstrainedRow &row : cell_rows[c])
          {
            vertex_rows[pv].push_back(row);
            face_rows[pf].push_back(row);
          }
      }

    // Every vertex-connected part needs Dirichlet nodes fixing all six
    // rigid motions.
    require_supported_parts(tria, by_vertex, vertex_rows, "node");

    const std::vector<Point<3>> &vertices = tria.get_vertices();
    std::map<std::size_t, std::vector<unsigned int>> shared_vertices;
    for (unsigned int v = 0; v < vertices.size(); ++v)
      if (parts_at_vertex[v].size() > 1)
        for (const std::size_t part : parts_at_vertex[v])
          shared_vertices[part].push_back(v);
    const auto mechanism = [](const unsigned int cells,
                              const Point<3>    &where,
                              const std::string &attached,
                              const unsigned int n_free) {
      return ExcMessage(std::to_string(cells) + " voxel(s) around " +
                        format_point(where) + " m" + attached +
                        ", which leaves " + std::to_string(n_free) +
                        " free mechanism motion(s). Fill or empty the "
                        "voxels at the joint so parts share faces.");
    };

    // The rows of face-connected part p and, in every direction, those of
    // its shared vertices that @p pinned selects.
    const auto rows_pinned = [&](const std::size_t p, const auto &pinned) {
      std::vector<ConstrainedRow> rows = face_rows[p];
      for (const unsigned int v : shared_vertices[p])
        if (pinned(v))
          for (unsigned int d = 0; d < 3; ++d)
            rows.emplace_back(vertices[v], d);
      return rows;
    };

    // A face-connected part that hangs on its neighbors only by nodes on
    // one edge or corner is a mechanism, even with its shared nodes
    // pinned.
    for (const auto &[p, part] : face_parts)
      {
        const unsigned int fixed =
          fixed_rigid_modes(rows_pinned(p, [](unsigned int) { return true; }));
        AssertThrow(fixed == 6,
                    mechanism(part.cells,
                              part.first_center,
                              " are attached to the rest only along an "
                              "edge or at a corner",
                              6 - fixed));
      }

    // Parts that hold each other up may still hang on the rest together.
    // A part is held if its rows and the nodes it shares with held parts
    // fix its rigid motions (examined again whenever a neighbor becomes
    // held); the others form groups joined by shared nodes, each of which
    // must be held as a whole.
    std::set<std::size_t> held;
    // Whether a held part touches vertex v.
    const auto at_held = [&](const unsigned int v) {
      return std::any_of(parts_at_vertex[v].begin(),
                         parts_at_vertex[v].end(),
                         [&](const std::size_t q) {
                           return held.count(q) > 0;
                         });
    };
    // The parts to examine, each queued once: it is examined with the
    // parts held by then.
    std::deque<std::size_t> to_examine;
    std::set<std::size_t>   queued;
    for (const auto &[p, part] : face_parts)
      {
        to_examine.push_back(p);
        queued.insert(p);
      }
    while (!to_examine.empty())
      {
        const std::size_t p = to_examine.front();
        to_examine.pop_front();
        queued.erase(p);
        if (held.count(p) > 0 || fixed_rigid_modes(rows_pinned(p, at_held)) < 6)
          continue;
        held.insert(p);
        for (const unsigned int v : shared_vertices[p])
          for (const std::size_t q : parts_at_vertex[v])
            if (held.count(q) == 0 && queued.insert(q).second)
              to_examine.push_back(q);
      }
    if (held.size() == face_parts.size())
      return;

    // The groups of the parts not held, joined at the nodes where no held
    // part holds them, and their conditions (the parts of a group are
    // numbered from 0).
    Components groups(tria.n_active_cells());
    for (unsigned int v = 0; v < vertices.size(); ++v)
      if (parts_at_vertex[v].size() > 1 && !at_held(v))
        for (const std::size_t p : parts_at_vertex[v])
          groups.join(p, *parts_at_vertex[v].begin());
    std::map<std::size_t, std::vector<std::size_t>> members;
    for (const auto &[p, part] : face_parts)
      if (held.count(p) == 0)
        members[groups.find(p)].push_back(p);
    std::map<std::size_t, RigidPartConditions> conditions;
    std::map<std::size_t, unsigned int>        number;
    for (const auto &[group, parts] : members)
      {
        Point<3> lower = face_parts[parts[0]].lower,
                 upper = face_parts[parts[0]].upper;
        for (const std::size_t p : parts)
          for (unsigned int d = 0; d < 3; ++d)
            {
              lower[d] = std::min(lower[d], face_parts[p].lower[d]);
              upper[d] = std::max(upper[d], face_parts[p].upper[d]);
            }
        conditions.emplace(group,
                           RigidPartConditions(parts.size(),
                                               0.5 * (lower + upper),
                                               0.5 * lower.distance(upper)));
        for (unsigned int i = 0; i < parts.size(); ++i)
          number[parts[i]] = i;
      }

    // A group's own rows and the nodes held parts share with it hold it;
    // the nodes its parts share with each other join them.
    for (const auto &[p, i] : number)
      {
        RigidPartConditions &group = conditions.at(groups.find(p));
        for (const ConstrainedRow &row : face_rows[p])
          group.hold(row.first, row.second, i);
        for (const unsigned int v : shared_vertices[p])
          for (unsigned int d = 0; d < 3; ++d)
            if (at_held(v))
              group.hold(vertices[v], d, i);
            else if (const std::size_t first = *parts_at_vertex[v].begin();
                     first != p)
              group.join(vertices[v], d, number.at(first), i);
      }
    for (const auto &[group, motions] : conditions)
      {
        const unsigned int n_free = motions.n_free_motions();
        unsigned int       cells  = 0;
        for (const std::size_t p : members[group])
          cells += face_parts[p].cells;
        AssertThrow(n_free == 0,
                    mechanism(cells,
                              face_parts[members[group][0]].first_center,
                              ", in " + std::to_string(members[group].size()) +
                                " parts, share only edges or corners with "
                                "each other and with the rest",
                              n_free));
      }
  }



  scene::BoundaryFace
  voxel_face(const Triangulation<3>::active_cell_iterator &cell,
             const unsigned int                            f)
  {
    return {cell->face(f)->center(),
            GeometryInfo<3>::unit_normal_vector[f],
            cell->extent_in_direction(0)};
  }



  void
  check_voxel_scene(const scene::Scene &scene)
  {
    Triangulation<3> tria;
    scene::make_voxel_mesh(scene.grid, 0, tria);
    const scene::BoundaryConditions &bc = scene.boundary_conditions;

    // Every condition acts on a vertex or a boundary face of the voxels.
    std::vector<scene::BoundaryFace> faces;
    if (bc.has_traction())
      for (const auto &cell : tria.active_cell_iterators())
        for (const unsigned int f : cell->face_indices())
          if (cell->face(f)->at_boundary())
            faces.push_back(voxel_face(cell, f));
    const std::vector<Point<3>> &vertices = tria.get_vertices();
    bc.check_regions(vertices, faces);
    bc.check_effects(vertices, faces, 1, false);

    // The held components of each vertex, then the rows of each cell.
    std::vector<std::vector<unsigned int>> held(vertices.size());
    for (unsigned int v = 0; v < vertices.size(); ++v)
      for (unsigned int d = 0; d < 3; ++d)
        if (double value; bc.prescribed_displacement(vertices[v], d, 1, value))
          held[v].push_back(d);
    std::vector<std::vector<ConstrainedRow>> cell_rows(tria.n_active_cells());
    for (const auto &cell : tria.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        for (const unsigned int d : held[cell->vertex_index(v)])
          cell_rows[cell->active_cell_index()].emplace_back(cell->vertex(v), d);
    require_supported_mesh(tria, cell_rows);
  }
} // namespace ddfem::solver
