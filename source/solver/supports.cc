#include <deal.II/base/exceptions.h>
#include <deal.II/fe/fe.h>

#include <ddfem/base/parsing.h>
#include <ddfem/solver/supports.h>

#include <algorithm>
#include <cmath>
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
        if (!cell->at_boundary(f))
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
            " m float free of the rest: they share no " + shared +
            " with the other parts, and Dirichlet conditions fix only " +
            std::to_string(fixed) +
            " of their 6 rigid body motions. Remove or connect them."));
      }
  }



  void
  require_supported_mesh(
    const Triangulation<3>                         &tria,
    const std::vector<std::vector<ConstrainedRow>> &cell_rows)
  {
    AssertThrow(
      std::any_of(cell_rows.begin(),
                  cell_rows.end(),
                  [](const auto &rows) { return !rows.empty(); }),
      ExcMessage(
        "No Dirichlet condition (fixed, sliding, displacement or "
        "rotation) acts on any node of the solid, so rigid body "
        "motions are not prevented. Add one in 'Boundary conditions'."));

    // Parts sharing nodes (vertex-connected cells) and parts sharing faces.
    Components by_vertex = vertex_connected_parts(tria);
    Components by_face   = face_connected_parts(tria);

    // Constrained rows per part; per vertex the face-connected parts
    // touching it.
    std::map<std::size_t, std::vector<ConstrainedRow>> vertex_rows, face_rows;
    std::map<std::size_t, std::pair<unsigned int, Point<3>>>
                                       part_size; // cells, a cell center
    std::vector<std::set<std::size_t>> parts_at_vertex(tria.n_vertices());
    for (const auto &cell : tria.active_cell_iterators())
      {
        const unsigned int c  = cell->active_cell_index();
        const std::size_t  pv = by_vertex.find(c), pf = by_face.find(c);
        auto              &size = part_size[pf];
        if (size.first++ == 0)
          size.second = cell->center();
        for (const unsigned int v : cell->vertex_indices())
          parts_at_vertex[cell->vertex_index(v)].insert(pf);
        for (const ConstrainedRow &row : cell_rows[c])
          {
            vertex_rows[pv].push_back(row);
            face_rows[pf].push_back(row);
          }
      }

    // Every vertex-connected part needs Dirichlet nodes fixing all six
    // rigid motions.
    require_supported_parts(tria, by_vertex, vertex_rows, "node");

    // A face-connected part that hangs on its neighbors only by nodes on
    // one edge or corner is a mechanism: count shared nodes as pinned.
    for (const auto &cell : tria.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        if (parts_at_vertex[cell->vertex_index(v)].size() > 1)
          for (unsigned int d = 0; d < 3; ++d)
            face_rows[by_face.find(cell->active_cell_index())].emplace_back(
              cell->vertex(v), d);
    for (const auto &[part, size] : part_size)
      {
        const unsigned int fixed = fixed_rigid_modes(face_rows[part]);
        AssertThrow(
          fixed == 6,
          ExcMessage(
            std::to_string(size.first) + " voxel(s) around " +
            format_point(size.second) +
            " m are attached to the rest only along an edge or at a "
            "corner, which leaves " +
            std::to_string(6 - fixed) +
            " free mechanism motion(s). Fill or empty the voxels at the "
            "joint so parts share faces."));
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
    bc.check_effects(vertices, faces);

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
