#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/timer.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_interface_values.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/meshworker/mesh_loop.h>
#include <deal.II/meshworker/scratch_data.h>

#include <ddfem/base/cell_values.h>
#include <ddfem/base/exceptions.h>
#include <ddfem/base/parsing.h>
#include <ddfem/base/statistics.h>
#include <ddfem/dg/system.h>
#include <ddfem/material/kernel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <tuple>
#include <utility>

namespace ddfem::dg
{
  std::string
  to_string(const Definiteness d)
  {
    switch (d)
      {
        case Definiteness::positive_definite:
          return "positive definite";
        case Definiteness::not_positive_definite:
          return "NOT positive definite";
        default:
          return "not checked";
      }
  }



  std::string
  unsolvable_system_causes()
  {
    return "the matrix is singular (a rigid motion that no boundary "
           "condition holds, or a fixed DG/Penalty too small: check it with "
           "'Penalty = automatic' on a smaller grid), or the loads, "
           "prescribed displacements or materials are beyond the range of "
           "double precision (a load far too large for a material far too "
           "soft, say)";
  }



  namespace
  {
    /// The stress of a field whose gradient is @p G (rows: components).
    template <int dim>
    Tensor<2, dim>
    flux(const Tensor<2, dim> &G,
         const CellMaterial   &m,
         const unsigned int    n_components)
    {
      return n_components == 1 ?
               Tensor<2, dim>(m.mu * G) :
               material::linear_elastic_stress(G, m.mu, m.lambda);
    }

    /// The penalty integrand of the jumps @p a, @p b at the normal @p n.
    template <int dim>
    double
    penalty_product(const Tensor<1, dim> &a,
                    const Tensor<1, dim> &b,
                    const Tensor<1, dim> &n,
                    const double          mu,
                    const double          lambda,
                    const unsigned int    n_components)
    {
      return n_components == 1 ? mu * (a * b) :
                                 2 * mu * (a * b) + lambda * (a * n) * (b * n);
    }

    /**
     * Block structure of a set of local degrees of freedom of a vector
     * element: the component of each, and for each the local indices of
     * the same scalar shape function in every component.
     */
    template <int dim>
    struct Blocks
    {
      std::vector<unsigned int>                  component;
      std::vector<std::array<unsigned int, dim>> partner;
    };

    /// The block structure of the dofs of one cell of @p fe.
    template <int dim>
    Blocks<dim>
    cell_blocks(const FiniteElement<dim> &fe)
    {
      Blocks<dim> b;
      for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
        {
          const auto [c, base] = fe.system_to_component_index(i);
          b.component.push_back(c);
          std::array<unsigned int, dim> p;
          for (unsigned int a = 0; a < dim; ++a)
            p[a] = fe.component_to_system_index(a, base);
          b.partner.push_back(p);
        }
      return b;
    }

    /**
     * The warped contribution of the local matrix @p A with the rotation
     * @p R (paper eq. 16): K += R A R^T, F -= R A (R^T x0 - x0), with x0
     * the local coefficients of the identity map.
     */
    template <int dim>
    void
    add_warped(const FullMatrix<double> &A,
               const Tensor<2, dim>     &R,
               const Blocks<dim>        &b,
               const Vector<double>     &x0,
               FullMatrix<double>       &K,
               Vector<double>           &F)
    {
      const unsigned int n = A.m();
      FullMatrix<double> AR(n, n);
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int j = 0; j < n; ++j)
          for (unsigned int a = 0; a < dim; ++a)
            AR(i, j) += A(i, b.partner[j][a]) * R[b.component[j]][a];
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int j = 0; j < n; ++j)
          for (unsigned int a = 0; a < dim; ++a)
            K(i, j) += R[b.component[i]][a] * AR(b.partner[i][a], j);

      Vector<double> d(n), y(n);
      for (unsigned int i = 0; i < n; ++i)
        {
          for (unsigned int a = 0; a < dim; ++a)
            d[i] += R[a][b.component[i]] * x0[b.partner[i][a]];
          d[i] -= x0[i];
        }
      A.vmult(y, d);
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int a = 0; a < dim; ++a)
          F[i] -= R[b.component[i]][a] * y[b.partner[i][a]];
    }

    /// F += R r for a local force @p r in the rotated frame.
    template <int dim>
    void
    add_rotated(const Vector<double> &r,
                const Tensor<2, dim> &R,
                const Blocks<dim>    &b,
                Vector<double>       &F)
    {
      for (unsigned int i = 0; i < r.size(); ++i)
        for (unsigned int a = 0; a < dim; ++a)
          F[i] += R[b.component[i]][a] * r[b.partner[i][a]];
    }

    /// Local matrix, vector and dof indices of one face.
    struct FaceCopy
    {
      std::vector<types::global_dof_index> dofs;
      FullMatrix<double>                   matrix;
      Vector<double>                       vector;
    };

    /// Local contributions of one cell, its boundary faces and its faces.
    struct CopyData
    {
      std::vector<types::global_dof_index> dofs;
      FullMatrix<double>                   matrix;
      Vector<double>                       vector;
      std::vector<FaceCopy>                faces;
    };

    /**
     * The rotation closest to @p A in the Frobenius norm, U diag(1, ..., 1,
     * det(U V^T)) V^T from the singular value decomposition A = U S V^T
     * (singular values in decreasing order). Where det A > 0 this is the
     * orthogonal factor of the polar decomposition of A. Where A is
     * inverted (det A < 0) that factor is a reflection, and where A is flat
     * (det A = 0) it is not unique; the sign fix of the smallest singular
     * value's vectors gives a proper rotation in both cases.
     */
    template <int dim>
    Tensor<2, dim>
    closest_rotation(const Tensor<2, dim> &A)
    {
      LAPACKFullMatrix<double> svd(dim, dim);
      for (unsigned int i = 0; i < dim; ++i)
        for (unsigned int j = 0; j < dim; ++j)
          svd(i, j) = A[i][j];
      svd.compute_svd();
      Tensor<2, dim> U, VT;
      for (unsigned int i = 0; i < dim; ++i)
        for (unsigned int j = 0; j < dim; ++j)
          {
            U[i][j]  = svd.get_svd_u()(i, j);
            VT[i][j] = svd.get_svd_vt()(i, j);
          }
      if (determinant(U) * determinant(VT) < 0)
        for (unsigned int i = 0; i < dim; ++i)
          U[i][dim - 1] = -U[i][dim - 1];
      return U * VT;
    }

    /**
     * The penalty's weight of the interior face that @p fiv is
     * reinitialized to, without eta: its area times the sum of the inverse
     * volumes of its two cells @p cell and @p ncell, |F| (1/|K| + 1/|K'|)
     * (eq. (7) of the DG paper).
     */
    template <int dim, typename Iterator>
    double
    interior_face_weight(const FEInterfaceValues<dim> &fiv,
                         const Iterator               &cell,
                         const Iterator               &ncell)
    {
      double area = 0;
      for (unsigned int q = 0; q < fiv.n_quadrature_points; ++q)
        area += fiv.JxW(q);
      return area * (1 / cell->measure() + 1 / ncell->measure());
    }

    /**
     * The penalty's weight of face @p face_no of @p cell as a boundary
     * face, without eta: 2 |F| / |K|, the interior weight with the cell's
     * mirror image as its neighbour. |F| is the whole face, also where
     * the cell is the coarse side of a hanging interior face held by
     * Nitsche's terms (the subface's area would weaken the penalty there
     * by the number of subfaces).
     */
    template <typename Iterator>
    double
    boundary_face_weight(const Iterator &cell, const unsigned int face_no)
    {
      return 2 * cell->face(face_no)->measure() / cell->measure();
    }

    /// What MeshWorker::mesh_loop() calls on an interior face.
    template <int dim, typename CopyDataType>
    using FaceWorker =
      std::function<void(const typename DoFHandler<dim>::active_cell_iterator &,
                         const unsigned int,
                         const unsigned int,
                         const typename DoFHandler<dim>::active_cell_iterator &,
                         const unsigned int,
                         const unsigned int,
                         MeshWorker::ScratchData<dim> &,
                         CopyDataType &)>;

    /**
     * The face worker of MeshWorker::mesh_loop() that sets up the interface
     * values of the scratch data on the face between a cell (face f) and
     * its neighbor (face nf) and calls @p worker(cell, f, neighbor, nf,
     * interface values, copy data).
     */
    template <int dim, typename CopyDataType, typename Worker>
    FaceWorker<dim, CopyDataType>
    interface_worker(const Worker &worker)
    {
      return [worker](const auto                   &cell,
                      const unsigned int            f,
                      const unsigned int            sf,
                      const auto                   &ncell,
                      const unsigned int            nf,
                      const unsigned int            nsf,
                      MeshWorker::ScratchData<dim> &s,
                      CopyDataType                 &c) {
        worker(cell, f, ncell, nf, s.reinit(cell, f, sf, ncell, nf, nsf), c);
      };
    }

    /// The side (0: the cell, 1: its neighbor) and the index within that
    /// side's cell of interface dof @p i: a DG dof lives on one side.
    template <int dim>
    std::pair<unsigned int, unsigned int>
    interface_dof_side(const FEInterfaceValues<dim> &fiv, const unsigned int i)
    {
      const auto         pair = fiv.interface_dof_to_dof_indices(i);
      const unsigned int side =
        pair[0] == numbers::invalid_unsigned_int ? 1 : 0;
      return {side, pair[side]};
    }

    /// The jump at face point @p q of the shape function @p local of
    /// @p side (the first side's value minus the second's), as a vector
    /// with one entry per field component (a scalar field uses entry 0).
    template <int dim>
    Tensor<1, dim>
    shape_jump(const FiniteElement<dim>     &fe,
               const FEInterfaceValues<dim> &fiv,
               const unsigned int            side,
               const unsigned int            local,
               const unsigned int            q)
    {
      Tensor<1, dim> jump;
      jump[fe.system_to_component_index(local).first] =
        (side == 0 ? 1. : -1.) *
        fiv.get_fe_face_values(side).shape_value(local, q);
      return jump;
    }
  } // namespace



  template <int dim>
  System<dim>::System(const Triangulation<dim> &triangulation,
                      const FiniteElement<dim> &scalar_fe,
                      const unsigned int        n_components,
                      const Parameters         &parameters,
                      const ProblemData<dim>   &data)
    : fe(scalar_fe, n_components)
    , dof_handler(triangulation)
    , parameters(parameters)
    , data(data)
    , n_components(n_components)
    , is_continuous(scalar_fe.n_dofs_per_face() > 0)
    , quadrature(scalar_fe.degree + 1)
    , face_quadrature(scalar_fe.degree + 1)
  {
    AssertThrow(n_components == 1 || n_components == dim,
                ExcMessage("A DG system has 1 (scalar) or dim (vector) "
                           "components, not " +
                           std::to_string(n_components) + "."));
    AssertThrow(data.materials.size() == triangulation.n_active_cells(),
                ExcMessage("One material per cell is needed."));
    dof_handler.distribute_dofs(fe);
    if (!is_continuous)
      {
        // FESystem numbers a cell's interior dofs component by component
        // (all x, then all y, ...). Algebraic multigrid reads consecutive
        // triples as the components of one node ('PDE equations'), so
        // number them node by node: the dof of component c at base dof i
        // goes to n_components i + c within its cell's block.
        std::vector<types::global_dof_index> renumbering(dof_handler.n_dofs()),
          dofs(fe.n_dofs_per_cell());
        for (const auto &cell : dof_handler.active_cell_iterators())
          {
            cell->get_dof_indices(dofs);
            const types::global_dof_index first =
              *std::min_element(dofs.begin(), dofs.end());
            Assert(*std::max_element(dofs.begin(), dofs.end()) ==
                     first + dofs.size() - 1,
                   ExcInternalError()); // a cell's dofs are one block
            for (unsigned int j = 0; j < dofs.size(); ++j)
              {
                const auto [c, i]    = fe.system_to_component_index(j);
                renumbering[dofs[j]] = first + n_components * i + c;
              }
          }
        dof_handler.renumber_dofs(renumbering);
      }
    for (unsigned int l = 0; l < triangulation.n_levels(); ++l)
      level_reference.push_back(dof_handler.begin_active(l));
    make_constraints(1);
    DynamicSparsityPattern dsp(dof_handler.n_dofs());
    if (is_continuous)
      DoFTools::make_sparsity_pattern(dof_handler, dsp, constraints, true);
    else
      {
        // The face terms of IP couple every dof of the two cells; the
        // penalty term of BZ only those non-zero on the face, and on
        // axis-aligned faces only equal components (paper Table 1).
        for (const auto &cell : triangulation.active_cell_iterators())
          for (const unsigned int f : cell->face_indices())
            {
              bool aligned = false;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  bool flat = true;
                  for (const unsigned int v : cell->face(f)->vertex_indices())
                    flat = flat && std::abs(cell->face(f)->vertex(v)[d] -
                                            cell->face(f)->vertex(0)[d]) <
                                     1e-12 * cell->diameter();
                  aligned = aligned || flat;
                }
              axis_aligned = axis_aligned && aligned;
            }
        const bool bz = parameters.flux == Parameters::Flux::babuska_zlamal;
        Table<2, DoFTools::Coupling> cell_mask(n_components, n_components);
        Table<2, DoFTools::Coupling> face_mask(n_components, n_components);
        cell_mask.fill(DoFTools::always);
        for (unsigned int c = 0; c < n_components; ++c)
          for (unsigned int d = 0; d < n_components; ++d)
            face_mask(c, d) = !bz                       ? DoFTools::always :
                              (c == d || !axis_aligned) ? DoFTools::nonzero :
                                                          DoFTools::none;
        DoFTools::make_flux_sparsity_pattern(dof_handler,
                                             dsp,
                                             constraints,
                                             true,
                                             cell_mask,
                                             face_mask,
                                             numbers::invalid_subdomain_id);
      }
    sparsity.copy_from(dsp);
    matrix.reinit(sparsity);
    rhs.reinit(dof_handler.n_dofs());
    solution.reinit(dof_handler.n_dofs());
    if (!is_continuous && n_components == dim)
      project_locally(Functions::IdentityFunction<dim>(), identity);
  }



  template <int dim>
  void
  System<dim>::make_constraints(const double t)
  {
    constraints.clear();
    if (is_continuous)
      DoFTools::make_hanging_node_constraints(dof_handler, constraints);
    const bool strong =
      is_continuous || parameters.dirichlet == Parameters::Dirichlet::strong;
    if (data.dirichlet && strong)
      {
        const auto &unit_points = fe.get_unit_support_points();
        AssertThrow(unit_points.size() == fe.n_dofs_per_cell(),
                    ExcMessage("Strong Dirichlet conditions need an element "
                               "with nodes (FE_Q, FE_DGQ), not " +
                               fe.get_name() + "."));
        // The nodes asked: every node (ProblemData::dirichlet_inside) or
        // those on boundary faces.
        const auto asked = [&](const auto &cell, const unsigned int i) {
          if (data.dirichlet_inside)
            return true;
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary() && on_unit_face(unit_points[i], f))
              return true;
          return false;
        };
        std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (data.dirichlet_inside || cell->at_boundary())
            {
              cell->get_dof_indices(dofs);
              for (unsigned int i = 0; i < dofs.size(); ++i)
                {
                  if (constraints.is_constrained(dofs[i]) || !asked(cell, i))
                    continue;
                  const Point<dim> p =
                    mapping.transform_unit_to_real_cell(cell, unit_points[i]);
                  double value = 0;
                  if (data.dirichlet(
                        p, fe.system_to_component_index(i).first, t, value))
                    {
                      constraints.add_line(dofs[i]);
                      constraints.set_inhomogeneity(dofs[i], value);
                    }
                }
            }
      }
    constraints.close();
  }



  template <int dim>
  void
  System<dim>::assemble(const double          eta,
                        const double          t,
                        const Vector<double> *current)
  {
    AssertThrow(current == nullptr || (!is_continuous && n_components == dim),
                ExcMessage("The corotated formulation needs a "
                           "discontinuous vector-valued element."));
    if (factor_of_matrix)
      {
        // The solves of cholesky_first keep the ordering for the next one.
        if (cholesky_first)
          check_factor.drop_factor();
        else
          check_factor.clear();
        factor_of_matrix = false;
      }
    eta_used = eta;
    make_constraints(t);
    matrix = 0;
    rhs    = 0;

    const std::vector<Tensor<2, dim>> cell_rotations =
      current ? rotations(*current) : std::vector<Tensor<2, dim>>();
    const Blocks<dim> blocks =
      n_components == dim ? cell_blocks<dim>(fe) : Blocks<dim>();
    const unsigned int n = fe.n_dofs_per_cell();
    const bool ip   = parameters.flux == Parameters::Flux::interior_penalty;
    const bool weak = parameters.dirichlet == Parameters::Dirichlet::weak &&
                      !is_continuous && bool(data.dirichlet);

    using Iterator = typename DoFHandler<dim>::active_cell_iterator;
    MeshWorker::ScratchData<dim> scratch(mapping,
                                         fe,
                                         quadrature,
                                         update_values | update_gradients |
                                           update_quadrature_points |
                                           update_JxW_values,
                                         face_quadrature,
                                         update_values | update_gradients |
                                           update_quadrature_points |
                                           update_JxW_values |
                                           update_normal_vectors);

    // The shape functions of a primitive vector element: e_c phi and
    // e_c (x) grad phi.
    const auto value_of = [](const unsigned int c, const double phi) {
      Tensor<1, dim> v;
      v[c] = phi;
      return v;
    };
    const auto gradient_of = [](const unsigned int    c,
                                const Tensor<1, dim> &grad) {
      Tensor<2, dim> G;
      G[c] = grad;
      return G;
    };
    const auto local_identity =
      [&](const std::vector<types::global_dof_index> &dofs) {
        Vector<double> x0(dofs.size());
        for (unsigned int i = 0; i < dofs.size(); ++i)
          x0[i] = identity[dofs[i]];
        return x0;
      };

    // The condition P (u - g) = 0 at x, if weak: P the projection onto the
    // components prescribed there (world frame), g their data.
    const auto held = [&](const Point<dim> &x, Tensor<1, dim> &g) {
      Tensor<2, dim> P;
      for (unsigned int d = 0; weak && d < n_components; ++d)
        if (data.dirichlet(x, d, t, g[d]))
          P[d][d] = 1;
      return P;
    };

    const auto cell_worker = [&](const Iterator               &cell,
                                 MeshWorker::ScratchData<dim> &s,
                                 CopyData                     &c) {
      const auto [fv, shift] = reinit_thread_independently<dim>(
        [&s](const Iterator &k) -> const FEValues<dim> & {
          return s.reinit(k);
        },
        cell,
        level_reference[cell->level()]);
      const CellMaterial &m = data.materials[cell->active_cell_index()];
      c.dofs.resize(n);
      cell->get_dof_indices(c.dofs);
      c.matrix.reinit(n, n);
      c.vector.reinit(n);
      c.faces.clear();
      FullMatrix<double>          A(n, n);
      std::vector<Tensor<2, dim>> stress(n);
      for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
        {
          for (unsigned int j = 0; j < n; ++j)
            stress[j] = flux(gradient_of(fe.system_to_component_index(j).first,
                                         fv.shape_grad(j, q)),
                             m,
                             n_components);
          Tensor<1, dim> f =
            data.body_force ?
              t * data.body_force(fv.quadrature_point(q) + shift) :
              Tensor<1, dim>();
          // A load on components held inside a Dirichlet region goes into
          // the reactions, as where strong conditions or CG hold them.
          if (weak && data.dirichlet_inside && data.body_force)
            {
              Tensor<1, dim> g;
              f -= held(fv.quadrature_point(q) + shift, g) * f;
            }
          for (unsigned int i = 0; i < n; ++i)
            {
              const unsigned int   ci = fe.system_to_component_index(i).first;
              const Tensor<1, dim> gi = fv.shape_grad(i, q);
              for (unsigned int j = 0; j < n; ++j)
                A(i, j) += gi * stress[j][ci] * fv.JxW(q);
              c.vector[i] += f[ci] * fv.shape_value(i, q) * fv.JxW(q);
            }
        }
      if (current)
        add_warped(A,
                   cell_rotations[cell->active_cell_index()],
                   blocks,
                   local_identity(c.dofs),
                   c.matrix,
                   c.vector);
      else
        c.matrix.add(1., A);
    };

    // Nitsche's terms on face @p face_no of @p cell, to which @p fv is
    // reinitialized (or to a subface of it): a boundary face, or one side
    // of an interior face inside a Dirichlet region
    // (ProblemData::dirichlet_inside). Added to @p matrix and @p vector,
    // whose rows are the cell's dofs @p dofs.
    const auto add_nitsche = [&](
                               const Iterator              &cell,
                               const unsigned int           face_no,
                               const FEFaceValuesBase<dim> &fv,
                               const std::vector<types::global_dof_index> &dofs,
                               FullMatrix<double> &matrix,
                               Vector<double>     &vector) {
      const CellMaterial &m     = data.materials[cell->active_cell_index()];
      const double        eta_f = eta * boundary_face_weight(cell, face_no);
      // Nitsche's consistency and symmetry terms and their Dirichlet data
      // part, in the element's frame (warped with its rotation R if
      // corotated). The penalty term as if warped: its isotropic part
      // 2 mu |P (u - g)|^2 is the same in both frames, and its part
      // lambda (P (u - g) . R n)^2 takes the element's turned normal R n,
      // as the consistency terms do; with the reference normal n the force
      // of a rotated configuration would not be the rotated force, and the
      // penalty would not control the consistency terms' lambda part.
      FullMatrix<double>          nitsche(n, n);
      Vector<double>              nitsche_data(n);
      const Tensor<2, dim>        R = current ?
                                        cell_rotations[cell->active_cell_index()] :
                                        unit_symmetric_tensor<dim>();
      std::vector<Tensor<2, dim>> stress(n);
      std::vector<Tensor<1, dim>> masked(n), masked_R(n);
      for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
        {
          const Point<dim>     &x   = fv.quadrature_point(q);
          const Tensor<1, dim> &nq  = fv.normal_vector(q);
          const Tensor<1, dim>  n_R = R * nq;
          const double          dx  = fv.JxW(q);
          // For the unrotated displacement u_R = R^T (x + u) - x of the
          // element frame the condition reads P_R (u_R - g_R) = 0 with P_R =
          // R^T P R and g_R = R^T (x + g) - x, so that only prescribed world
          // components are held, also where only some are (sliding). With
          // R = I, g_R = g exactly.
          Tensor<1, dim>       g;
          const Tensor<2, dim> P = held(x, g);
          if (P.norm_square() == 0)
            continue;
          const Tensor<2, dim> P_R = transpose(R) * P * R;
          const Tensor<1, dim> g_R = transpose(R) * g + (transpose(R) * x - x);
          const Tensor<1, dim> Pg  = P * g;
          const Tensor<1, dim> P_R_g_R = P_R * g_R;
          for (unsigned int j = 0; j < n; ++j)
            {
              const unsigned int   cj  = fe.system_to_component_index(j).first;
              const Tensor<1, dim> phi = value_of(cj, fv.shape_value(j, q));
              stress[j] =
                flux(gradient_of(cj, fv.shape_grad(j, q)), m, n_components);
              masked[j]   = P * phi;
              masked_R[j] = P_R * phi;
            }
          for (unsigned int i = 0; i < n; ++i)
            {
              const Tensor<1, dim> si = stress[i] * nq;
              vector[i] += eta_f *
                           penalty_product(Pg,
                                           masked[i],
                                           n_R,
                                           m.mu,
                                           std::max(m.lambda, 0.),
                                           n_components) *
                           dx;
              // -(u - g).sigma(v) n: the data part moves to F.
              if (ip)
                nitsche_data[i] -= (P_R_g_R * si) * dx;
              for (unsigned int j = 0; j < n; ++j)
                {
                  matrix(i, j) += eta_f *
                                  penalty_product(masked[i],
                                                  masked[j],
                                                  n_R,
                                                  m.mu,
                                                  std::max(m.lambda, 0.),
                                                  n_components) *
                                  dx;
                  if (ip)
                    nitsche(i, j) -=
                      (masked_R[i] * (stress[j] * nq) + masked_R[j] * si) * dx;
                }
            }
        }
      if (current)
        {
          add_warped(nitsche, R, blocks, local_identity(dofs), matrix, vector);
          add_rotated(nitsche_data, R, blocks, vector);
        }
      else
        {
          matrix.add(1., nitsche);
          vector += nitsche_data;
        }
    };

    const auto boundary_worker = [&](const Iterator               &cell,
                                     const unsigned int            face_no,
                                     MeshWorker::ScratchData<dim> &s,
                                     CopyData                     &c) {
      const FEFaceValuesBase<dim> &fv = s.reinit(cell, face_no);
      if (data.traction)
        {
          // A load on prescribed components goes into the reactions, as
          // where strong conditions or CG constrain them.
          const Point<dim> center = cell->face(face_no)->center();
          for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
            {
              const Point<dim>    &x = fv.quadrature_point(q);
              Tensor<1, dim>       g;
              const Tensor<2, dim> P = held(x, g);
              Tensor<1, dim>       tr =
                t * data.traction(center, x, fv.normal_vector(q));
              tr -= P * tr;
              for (unsigned int i = 0; i < n; ++i)
                c.vector[i] += tr[fe.system_to_component_index(i).first] *
                               fv.shape_value(i, q) * fv.JxW(q);
            }
        }
      add_nitsche(cell, face_no, fv, c.dofs, c.matrix, c.vector);
    };

    const auto face_worker = [&](const Iterator               &cell,
                                 const unsigned int            f,
                                 const Iterator               &ncell,
                                 const unsigned int            nf,
                                 const FEInterfaceValues<dim> &fiv,
                                 CopyData                     &c) {
      // Inside a Dirichlet region each side is held as on a boundary face,
      // as CG holds every node of the region: the components held at each
      // quadrature point (the sides share them), if any is.
      std::vector<Tensor<2, dim>> held_at;
      if (weak && data.dirichlet_inside)
        for (const Point<dim> &x :
             fiv.get_fe_face_values(0).get_quadrature_points())
          {
            Tensor<1, dim> g;
            held_at.push_back(held(x, g));
          }
      if (std::none_of(held_at.begin(),
                       held_at.end(),
                       [](const Tensor<2, dim> &P) {
                         return P.norm_square() > 0;
                       }))
        held_at.clear();
      for (unsigned int side = 0; side < 2 && !held_at.empty(); ++side)
        {
          const Iterator &k         = (side == 0 ? cell : ncell);
          FaceCopy       &held_side = c.faces.emplace_back();
          held_side.dofs.resize(n);
          k->get_dof_indices(held_side.dofs);
          held_side.matrix.reinit(n, n);
          held_side.vector.reinit(n);
          add_nitsche(k,
                      side == 0 ? f : nf,
                      fiv.get_fe_face_values(side),
                      held_side.dofs,
                      held_side.matrix,
                      held_side.vector);
        }

      const unsigned int n_if = fiv.n_current_interface_dofs();
      const std::array<const CellMaterial *, 2> m = {
        {&data.materials[cell->active_cell_index()],
         &data.materials[ncell->active_cell_index()]}};
      const double mu_f     = std::max(m[0]->mu, m[1]->mu);
      const double lambda_f = std::max({m[0]->lambda, m[1]->lambda, 0.});
      const double eta_f    = eta * interior_face_weight(fiv, cell, ncell);

      // Side and local index of every interface dof (one side each: DG).
      std::vector<unsigned int>                side(n_if), local(n_if);
      std::array<std::vector<unsigned int>, 2> interface_index = {
        {std::vector<unsigned int>(n), std::vector<unsigned int>(n)}};
      for (unsigned int i = 0; i < n_if; ++i)
        {
          std::tie(side[i], local[i])        = interface_dof_side(fiv, i);
          interface_index[side[i]][local[i]] = i;
        }

      FaceCopy                   &face     = c.faces.emplace_back();
      const auto                 &all_dofs = fiv.get_interface_dof_indices();
      std::vector<Tensor<1, dim>> jump(n_if);
      // The dofs whose shape functions are non-zero on the face (all of
      // FE_DGP's; of FE_DGQ's those with a support point on it): the others
      // have no jump there.
      const std::array<unsigned int, 2> face_no = {{f, nf}};
      std::vector<unsigned int>         used;
      for (unsigned int i = 0; i < n_if; ++i)
        if (fe.has_support_on_face(local[i], face_no[side[i]]))
          used.push_back(i);
      // The jump of interface dof i's shape function at point q.
      const auto jump_at = [&](const unsigned int i, const unsigned int q) {
        return shape_jump(fe, fiv, side[i], local[i], q);
      };
      if (!ip)
        {
          // Babuska-Zlamal: the penalty term only, on the dofs of the jump;
          // on axis-aligned faces it does not couple different components
          // (see the sparsity).
          for (const unsigned int i : used)
            face.dofs.push_back(all_dofs[i]);
          face.matrix.reinit(used.size(), used.size());
          face.vector.reinit(used.size());
          for (unsigned int q = 0; q < fiv.n_quadrature_points; ++q)
            {
              const Tensor<1, dim> nq = fiv.normal(q);
              for (const unsigned int i : used)
                jump[i] = jump_at(i, q);
              for (unsigned int a = 0; a < used.size(); ++a)
                for (unsigned int b = 0; b < used.size(); ++b)
                  if (!axis_aligned ||
                      fe.system_to_component_index(local[used[a]]).first ==
                        fe.system_to_component_index(local[used[b]]).first)
                    face.matrix(a, b) += eta_f *
                                         penalty_product(jump[used[a]],
                                                         jump[used[b]],
                                                         nq,
                                                         mu_f,
                                                         lambda_f,
                                                         n_components) *
                                         fiv.JxW(q);
            }
          return;
        }

      // Interior penalty: consistency and symmetry terms split by the side
      // whose stress they contain (paper section 7), and the penalty term.
      face.dofs = all_dofs;
      face.matrix.reinit(n_if, n_if);
      face.vector.reinit(n_if);
      std::array<FullMatrix<double>, 2> A = {
        {FullMatrix<double>(n_if, n_if), FullMatrix<double>(n_if, n_if)}};
      std::vector<Tensor<1, dim>> traction(n_if);
      // The jump's free part in each side's frame (see below).
      std::array<std::vector<Tensor<1, dim>>, 2> free_jump = {
        {std::vector<Tensor<1, dim>>(n_if), std::vector<Tensor<1, dim>>(n_if)}};
      for (unsigned int q = 0; q < fiv.n_quadrature_points; ++q)
        {
          const Tensor<1, dim> nq = fiv.normal(q);
          const double         dx = fiv.JxW(q);
          // Components held here (inside a Dirichlet region) have each
          // side's Nitsche terms instead of these consistency and symmetry
          // terms, which would count their traction twice: the terms of a
          // side's stress take the jump's free part in that side's frame.
          std::array<Tensor<2, dim>, 2> free_part = {
            {unit_symmetric_tensor<dim>(), unit_symmetric_tensor<dim>()}};
          if (!held_at.empty())
            {
              for (unsigned int s = 0; s < 2; ++s)
                if (current)
                  {
                    const Tensor<2, dim> &R =
                      cell_rotations[(s == 0 ? cell : ncell)
                                       ->active_cell_index()];
                    free_part[s] -= transpose(R) * held_at[q] * R;
                  }
                else
                  free_part[s] -= held_at[q];
            }
          for (unsigned int i = 0; i < n_if; ++i)
            {
              const FEFaceValuesBase<dim> &fv = fiv.get_fe_face_values(side[i]);
              const unsigned int           ci =
                fe.system_to_component_index(local[i]).first;
              traction[i] = flux(gradient_of(ci, fv.shape_grad(local[i], q)),
                                 *m[side[i]],
                                 n_components) *
                            nq;
            }
          for (const unsigned int i : used)
            {
              jump[i] = jump_at(i, q);
              for (unsigned int s = 0; s < 2; ++s)
                free_jump[s][i] = free_part[s] * jump[i];
            }
          // The consistency and symmetry terms of the jumps' dofs with
          // every dof's traction, and the penalty of the jumps.
          for (const unsigned int i : used)
            for (unsigned int j = 0; j < n_if; ++j)
              {
                A[side[j]](i, j) -=
                  0.5 * (free_jump[side[j]][i] * traction[j]) * dx;
                A[side[j]](j, i) -=
                  0.5 * (free_jump[side[j]][i] * traction[j]) * dx;
              }
          for (const unsigned int i : used)
            for (const unsigned int j : used)
              face.matrix(i, j) +=
                eta_f *
                penalty_product(
                  jump[i], jump[j], nq, mu_f, lambda_f, n_components) *
                dx;
        }
      if (current)
        {
          // The penalty term is warped too, half with each side's rotation.
          // That leaves its isotropic part 2 mu [u].[v] unchanged (the paper
          // does not warp the penalty), and turns its part lambda ([u].n)
          // ([v].n) with the elements: unwarped, the force of a rotated
          // configuration would not be the rotated force.
          A[0].add(0.5, face.matrix);
          A[1].add(0.5, face.matrix);
          face.matrix = 0;
          Blocks<dim> b;
          for (unsigned int i = 0; i < n_if; ++i)
            {
              b.component.push_back(blocks.component[local[i]]);
              std::array<unsigned int, dim> p;
              for (unsigned int a = 0; a < dim; ++a)
                p[a] = interface_index[side[i]][blocks.partner[local[i]][a]];
              b.partner.push_back(p);
            }
          const Vector<double> x0 = local_identity(face.dofs);
          add_warped(A[0],
                     cell_rotations[cell->active_cell_index()],
                     b,
                     x0,
                     face.matrix,
                     face.vector);
          add_warped(A[1],
                     cell_rotations[ncell->active_cell_index()],
                     b,
                     x0,
                     face.matrix,
                     face.vector);
        }
      else
        {
          face.matrix.add(1., A[0]);
          face.matrix.add(1., A[1]);
        }
    };

    Timer      copy_timer(MPI_COMM_SELF, false);
    const auto copier = [&](const CopyData &c) {
      copy_timer.start();
      constraints.distribute_local_to_global(
        c.matrix, c.vector, c.dofs, matrix, rhs);
      for (const FaceCopy &face : c.faces)
        constraints.distribute_local_to_global(
          face.matrix, face.vector, face.dofs, matrix, rhs);
      copy_timer.stop();
    };

    Timer total;
    auto  flags =
      MeshWorker::assemble_own_cells | MeshWorker::assemble_boundary_faces;
    if (!is_continuous)
      flags |= MeshWorker::assemble_own_interior_faces_once;
    CopyData copy;
    // mesh_loop wants a face worker exactly if faces are worked on.
    MeshWorker::mesh_loop(dof_handler.begin_active(),
                          dof_handler.end(),
                          cell_worker,
                          copier,
                          scratch,
                          copy,
                          flags,
                          boundary_worker,
                          is_continuous ?
                            FaceWorker<dim, CopyData>() :
                            interface_worker<dim, CopyData>(face_worker));
    total.stop();
    assembly_time    = copy_timer.wall_time();
    integration_time = total.wall_time() - assembly_time;
  }



  template <int dim>
  Definiteness
  System<dim>::check_definiteness()
  {
    solver::SparseCholesky cholesky;
    return check_definiteness(cholesky);
  }



  template <int dim>
  Definiteness
  System<dim>::check_definiteness(solver::SparseCholesky &cholesky)
  {
    // Sparse Cholesky (CHOLMOD, with a fill-reducing ordering): its
    // symbolic analysis gives the size of the factor before any numerical
    // work.
    // A factor too large for CHOLMOD's indices has infinitely many values.
    factor_values = cholesky.analyze(matrix);
    if (factor_values > parameters.definiteness_check_limit)
      return Definiteness::not_checked;
    if (!cholesky.factorize(matrix))
      return Definiteness::not_positive_definite;
    // A matrix that is singular in exact arithmetic (a penalty at the
    // threshold, a free rigid motion) can factorize in floating point with a
    // pivot at round-off level: 12 digits of a diagonal entry cancelled are
    // taken as a zero pivot. The smallest ratio in the DG tests is 9e-9
    // (thin elements), and a stiffness contrast of 1e6 stays above 1.1e-10
    // up to eta = 2^30; settle_penalty() names the materials that take the
    // check beyond floating point.
    if (cholesky.smallest_pivot_ratio() < singular_pivot_ratio)
      return Definiteness::not_positive_definite;
    return Definiteness::positive_definite;
  }



  template <int dim>
  Definiteness
  System<dim>::settle_penalty(const double t)
  {
    // One factor serves the doublings (the ordering is kept) and, if asked
    // for, the solve of the matrix it passed; on an error it is freed.
    check_factor.clear();
    factor_of_matrix = false;
    try
      {
        const Definiteness d = search_penalty(t);
        factor_of_matrix =
          solve_with_check_factor && d == Definiteness::positive_definite;
        if (!factor_of_matrix)
          check_factor.clear();
        return d;
      }
    catch (...)
      {
        check_factor.clear();
        throw;
      }
  }



  template <int dim>
  Definiteness
  System<dim>::search_penalty(const double t)
  {
    penalty_doublings = 0;
    if (is_continuous)
      {
        assemble(0, t);
        return check_definiteness(check_factor);
      }
    parameters.check_penalty(parameters.flux, "DG/Flux = babuska-zlamal");
    // Materials beyond what the check resolves in floating point are a
    // cause of their own (measured on prm/default.prm with Method = dg): a
    // nearly incompressible one loses its divergence-free modes in
    // round-off (one material passes at lambda/mu = 5e10, nu =
    // 0.49999999999, and fails at 5e12), and where a stiff part is held
    // only by a soft one its pivots fall to about 0.2 / (contrast eta) of
    // their diagonal (palettes E = 1, 1e3 and 1e7 to 1e10 Pa): contrast 1e7
    // passes up to eta = 1e4, 1e9 up to eta = 100, 1e10 only at the
    // automatic eta = 4.
    double incompressibility = 0, softest = data.materials[0].mu, stiffest = 0;
    for (const CellMaterial &m : data.materials)
      {
        incompressibility = std::max(incompressibility, m.lambda / m.mu);
        softest           = std::min(softest, m.mu);
        stiffest          = std::max(stiffest, m.mu);
      }
    std::ostringstream limits;
    if (incompressibility > 5e10)
      limits << " Or the material is too close to incompressible for the "
                "check in floating point (lambda/mu up to "
             << incompressibility << "; 5e10 still passes): use a smaller "
             << "Poisson ratio.";
    if (stiffest / softest > 1e7)
      limits << " Or the shear moduli, which span a factor of "
             << stiffest / softest
             << ", differ too much for the check in floating point: where a "
                "stiff part is held only by a soft one, its pivots fall to "
                "about 0.2 / (that factor x eta) of their diagonal, and below "
                "1e-12 they count as zero (a factor of 1e9 passes up to eta "
                "= 100; a larger penalty makes it worse).";
    if (!parameters.automatic_penalty())
      {
        assemble(parameters.penalty, t);
        const Definiteness d = check_definiteness(check_factor);
        std::ostringstream eta;
        eta << parameters.penalty;
        AssertThrow(d != Definiteness::not_positive_definite,
                    ExcMessage(
                      "DG/Penalty = " + eta.str() +
                      " is too small: the stiffness matrix is not positive "
                      "definite (or the Dirichlet conditions do not prevent "
                      "rigid motions). Use a larger penalty" +
                      (parameters.flux == Parameters::Flux::babuska_zlamal ?
                         std::string(".") :
                         std::string(", or 'automatic' if no method of the "
                                     "run uses the Babuska-Zlamal flux (Run "
                                     "type = dg cost always compares with "
                                     "it).")) +
                      limits.str()));
        return d;
      }
    double eta = 1;
    for (; penalty_doublings <= 30; ++penalty_doublings, eta *= 2)
      {
        assemble(eta, t);
        const Definiteness d = check_definiteness(check_factor);
        std::ostringstream size;
        if (std::isinf(factor_values))
          size << "more values than CHOLMOD's 32-bit indices count. Give a "
                  "fixed DG/Penalty.";
        else
          size << factor_values
               << " values, more than DG/Definiteness check limit = "
               << parameters.definiteness_check_limit
               << " (8 bytes each). Raise the limit or give a fixed "
                  "DG/Penalty.";
        AssertThrow(
          d != Definiteness::not_checked,
          ExcMessage(
            "DG/Penalty = automatic checks positive definiteness by a sparse "
            "Cholesky factorization, but its factor for this system (" +
            std::to_string(dof_handler.n_dofs()) + " DoFs) stores " +
            size.str() +
            " For the "
            "penalty, take twice the value found automatically on a "
            "coarser grid of the same part: eq. 7 scales it with the "
            "cells, but the smallest stable value also depends on the "
            "part's boundary and materials."));
        if (d == Definiteness::positive_definite)
          return d;
      }
    AssertThrow(false,
                ExcMessage("DG/Penalty = automatic: no penalty up to 2^30 "
                           "gives a positive definite stiffness matrix; do "
                           "the Dirichlet conditions prevent rigid motions?" +
                           limits.str()));
    return Definiteness::not_positive_definite;
  }



  template <int dim>
  void
  System<dim>::solve()
  {
    Timer timer;
    if (!factor_of_matrix && cholesky_first)
      {
        factor_of_matrix = check_factor.factorize(matrix);
        if (!factor_of_matrix)
          cholesky_first = false; // one failed factorization is enough
      }
    if (factor_of_matrix)
      {
        check_factor.vmult(solution, rhs);
        ++cholesky_solves;
      }
    else if (linear_solver)
      linear_solver(matrix, solution, rhs);
    else
      {
        SparseDirectUMFPACK direct;
        try
          {
            direct.initialize(matrix);
          }
        catch (const ExceptionBase &e)
          {
            AssertThrow(false,
                        ExcMessage("UMFPACK could not factorize the DG "
                                   "system (" +
                                   std::to_string(dof_handler.n_dofs()) +
                                   " DoFs): " + message_of(e) + " Either " +
                                   unsolvable_system_causes() +
                                   ", or memory ran out (a grid too large)."));
          }
        direct.vmult(solution, rhs);
      }
    constraints.distribute(solution);
    AssertThrow(all_finite(solution),
                ExcMessage("The DG solution is not finite: either " +
                           unsolvable_system_causes() + "."));
    solve_time = timer.wall_time();
  }



  template <int dim>
  unsigned int
  System<dim>::run()
  {
    if (parameters.formulation == Parameters::Formulation::linear)
      {
        solve();
        return 1;
      }
    // Each solve with the rotations of the iterate u_k gives G(u_k). The
    // lagged iteration u_k+1 = G(u_k) converges ever more slowly as the
    // rotations grow (slender parts under a large twist), along modes that
    // shrink by a factor c per iteration or alternate in sign (c < 0).
    // Aitken's dynamic relaxation (Irons and Tuck) takes u_k+1 = u_k +
    // omega_k r_k with r_k = G(u_k) - u_k and omega_k = -omega_k-1
    // r_k-1.(r_k - r_k-1) / |r_k - r_k-1|^2, from omega = 1 in each load
    // step: along a dominant mode it steps by 1 / (1 - c), which damps an
    // alternating mode (omega < 1) and extrapolates a slow one (omega > 1).
    // Where c nears 1 (a compressed slender part at its buckling load)
    // omega jumps to tens and overshoots along a mode that is not linear,
    // so |omega| is kept at most 10: c up to 0.9 is still fully
    // accelerated. The iteration stops at the solve G(u_k) whose change
    // r_k is small.
    const double max_relaxation = 10;
    unsigned int solves         = 0;
    solution                    = 0;
    Vector<double> iterate, residual, previous_residual;
    for (unsigned int step = 1; step <= parameters.load_steps; ++step)
      {
        const double t     = double(step) / parameters.load_steps;
        double       omega = 1;
        for (unsigned int it = 1;; ++it)
          {
            iterate = solution;
            assemble(eta_used, t, &solution);
            solve();
            ++solves;
            residual = solution;
            residual -= iterate;
            const double change =
              residual.l2_norm() / std::max(solution.l2_norm(), 1e-300);
            if (change <= parameters.corotation_tolerance)
              break;
            const auto change_text = [&]() {
              std::ostringstream text;
              text << change
                   << " relative to its norm, above DG/Corotation tolerance = "
                   << parameters.corotation_tolerance;
              return text.str();
            };
            AssertThrow(it < parameters.corotation_iterations,
                        ExcMessage(
                          "The corotated iteration did not converge in "
                          "DG/Corotation iterations = " +
                          std::to_string(parameters.corotation_iterations) +
                          " at load step " + std::to_string(step) + " of " +
                          std::to_string(parameters.load_steps) +
                          ": its last solve changed the solution by " +
                          change_text() +
                          ". Use more DG/Load steps or DG/Corotation "
                          "iterations. (A slender part compressed to its "
                          "buckling load stalls the iteration at any step "
                          "size: doc/dg.md, 'Compressed past buckling'.)" +
                          stall_hint));
            if (it > 1)
              {
                // d = r_k-1 - r_k, so that omega_k = omega_k-1 (1 + r_k.d
                // / |d|^2); an unchanged residual keeps omega.
                previous_residual -= residual;
                const double d2 = previous_residual.norm_sqr();
                if (d2 > 0)
                  omega =
                    std::clamp(omega *
                                 (1 + (residual * previous_residual) / d2),
                               -max_relaxation,
                               max_relaxation);
              }
            solution = iterate;
            solution.add(omega, residual);
            previous_residual = residual;
          }
        // The lagged rotations have fixed points that are no deformation:
        // a twist too large for one step can settle with cells inside out
        // and the prescribed displacements missed by far (the elastic
        // energy of the corotated model, unlike the Neo-Hookean one, does
        // not grow without bound as a cell flattens).
        const auto [J, where] = smallest_jacobian(solution);
        if (!(J > 0))
          {
            std::ostringstream message;
            message << "The corotated iteration ended load step " << step
                    << " of " << parameters.load_steps
                    << " in a state that turns a cell inside out at "
                    << format_point(where)
                    << " m (det F = " << std::setprecision(3) << J
                    << " there): no deformation. Use more DG/Load steps, or "
                       "prescribe motions that every cell can follow.";
            AssertThrow(false, ExcMessage(message.str()));
          }
      }
    return solves;
  }



  template <int dim>
  std::pair<double, Point<dim>>
  System<dim>::smallest_jacobian(const Vector<double> &u) const
  {
    AssertDimension(n_components, dim);
    // The cell's vertices, where a cell turns inside out first, and its
    // quadrature points.
    std::vector<Point<dim>> points = QTrapezoid<dim>().get_points();
    points.insert(points.end(),
                  quadrature.get_points().begin(),
                  quadrature.get_points().end());
    FEValues<dim>                        fv(mapping,
                     fe,
                     Quadrature<dim>(points),
                     update_gradients | update_quadrature_points);
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    FirstSmallest<Point<dim>>            smallest;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        // The values may be those of a translate (reference): the cell's
        // own coefficients, as in rotations().
        const Tensor<1, dim> shift =
          reinit_thread_independently(fv, cell, level_reference[cell->level()])
            .shift;
        cell->get_dof_indices(dofs);
        for (unsigned int q = 0; q < points.size(); ++q)
          {
            Tensor<2, dim> F = unit_symmetric_tensor<dim>();
            for (unsigned int i = 0; i < dofs.size(); ++i)
              F[fe.system_to_component_index(i).first] +=
                u[dofs[i]] * fv.shape_grad(i, q);
            smallest.add(determinant(F), fv.quadrature_point(q) + shift);
          }
      }
    return {smallest.value(), smallest.place()};
  }



  template <int dim>
  void
  System<dim>::project_locally(const Function<dim> &function,
                               Vector<double>      &v) const
  {
    AssertThrow(!is_continuous,
                ExcMessage("A cellwise projection needs a discontinuous "
                           "element."));
    AssertDimension(function.n_components, fe.n_components());
    v.reinit(dof_handler.n_dofs());
    const unsigned int                   n = fe.n_dofs_per_cell();
    FEValues<dim>                        fv(mapping,
                     fe,
                     quadrature,
                     update_values | update_quadrature_points |
                       update_JxW_values);
    std::vector<types::global_dof_index> dofs(n);
    FullMatrix<double>                   M(n, n);
    Vector<double>                       b(n), x(n), values(fe.n_components());
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        const Tensor<1, dim> shift =
          reinit_thread_independently(fv, cell, level_reference[cell->level()])
            .shift;
        M = 0;
        b = 0;
        for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
          {
            function.vector_value(fv.quadrature_point(q) + shift, values);
            for (unsigned int i = 0; i < n; ++i)
              {
                const unsigned int ci = fe.system_to_component_index(i).first;
                b[i] += values[ci] * fv.shape_value(i, q) * fv.JxW(q);
                for (unsigned int j = 0; j < n; ++j)
                  if (fe.system_to_component_index(j).first == ci)
                    M(i, j) +=
                      fv.shape_value(i, q) * fv.shape_value(j, q) * fv.JxW(q);
              }
          }
        M.gauss_jordan();
        M.vmult(x, b);
        cell->get_dof_indices(dofs);
        for (unsigned int i = 0; i < n; ++i)
          v[dofs[i]] = x[i];
      }
  }



  template <int dim>
  std::vector<Tensor<2, dim>>
  System<dim>::rotations(const Vector<double> &u) const
  {
    std::vector<Tensor<2, dim>> R(
      dof_handler.get_triangulation().n_active_cells());
    FEValues<dim>                        fv(mapping,
                     fe,
                     quadrature,
                     update_values | update_quadrature_points |
                       update_JxW_values);
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        const Tensor<1, dim> shift =
          reinit_thread_independently(fv, cell, level_reference[cell->level()])
            .shift;
        cell->get_dof_indices(dofs);
        // Deformed positions y = x + u at the quadrature points, and the
        // least-squares affine fit y ~ A x + b.
        std::vector<Point<dim>> x(fv.get_quadrature_points());
        for (Point<dim> &p : x)
          p += shift;
        std::vector<Point<dim>> y(x);
        Point<dim>              x_mean, y_mean;
        double                  volume = 0;
        for (unsigned int q = 0; q < y.size(); ++q)
          {
            for (unsigned int i = 0; i < dofs.size(); ++i)
              y[q][fe.system_to_component_index(i).first] +=
                u[dofs[i]] * fv.shape_value(i, q);
            x_mean += fv.JxW(q) * x[q];
            y_mean += fv.JxW(q) * y[q];
            volume += fv.JxW(q);
          }
        x_mean /= volume;
        y_mean /= volume;
        Tensor<2, dim> XX, YX;
        for (unsigned int q = 0; q < y.size(); ++q)
          {
            const Tensor<1, dim> dx = x[q] - x_mean;
            const Tensor<1, dim> dy = y[q] - y_mean;
            XX += fv.JxW(q) * outer_product(dx, dx);
            YX += fv.JxW(q) * outer_product(dy, dx);
          }
        R[cell->active_cell_index()] = closest_rotation(YX * invert(XX));
      }
    return R;
  }



  template <int dim>
  double
  System<dim>::jump_norm(const Vector<double> &u,
                         const Function<dim>  *exact) const
  {
    Assert(exact == nullptr || exact->n_components == n_components,
           ExcDimensionMismatch(exact->n_components, n_components));
    using Iterator = typename DoFHandler<dim>::active_cell_iterator;
    MeshWorker::ScratchData<dim> scratch(mapping,
                                         fe,
                                         quadrature,
                                         update_values,
                                         face_quadrature,
                                         update_values | update_JxW_values |
                                           update_quadrature_points);
    double                       sum = 0;
    // Interior faces: the jump of u, which that of a continuous exact
    // solution does not change.
    const auto face_worker = [&](const Iterator &cell,
                                 const unsigned int,
                                 const Iterator &ncell,
                                 const unsigned int,
                                 const FEInterfaceValues<dim> &fiv,
                                 double                       &c) {
      const auto &dofs        = fiv.get_interface_dof_indices();
      double      jump_square = 0;
      for (unsigned int q = 0; q < fiv.n_quadrature_points; ++q)
        {
          Tensor<1, dim> jump;
          for (unsigned int i = 0; i < dofs.size(); ++i)
            {
              const auto [side, local] = interface_dof_side(fiv, i);
              jump += u[dofs[i]] * shape_jump(fe, fiv, side, local, q);
            }
          jump_square += jump.norm_square() * fiv.JxW(q);
        }
      c += interior_face_weight(fiv, cell, ncell) * jump_square;
    };
    // Boundary faces: the trace of u - exact.
    const auto boundary_worker = [&](const Iterator               &cell,
                                     const unsigned int            f,
                                     MeshWorker::ScratchData<dim> &s,
                                     double                       &c) {
      const FEFaceValuesBase<dim> &fv = s.reinit(cell, f);
      std::vector<Vector<double>>  values(fv.n_quadrature_points,
                                         Vector<double>(n_components));
      fv.get_function_values(u, values);
      Vector<double> exact_value(n_components);
      double         trace_square = 0;
      for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
        {
          exact->vector_value(fv.quadrature_point(q), exact_value);
          values[q] -= exact_value;
          trace_square += values[q].norm_sqr() * fv.JxW(q);
        }
      c += boundary_face_weight(cell, f) * trace_square;
    };
    // A shared DoF has the same value on both sides: FE_Q has no jumps (the
    // face worker would measure traces). mesh_loop wants a worker exactly
    // for the faces worked on.
    auto flags = MeshWorker::assemble_own_cells;
    if (!is_continuous)
      flags |= MeshWorker::assemble_own_interior_faces_once;
    if (exact != nullptr)
      flags |= MeshWorker::assemble_boundary_faces;
    using BoundaryWorker = std::function<void(const Iterator &,
                                              const unsigned int,
                                              MeshWorker::ScratchData<dim> &,
                                              double &)>;
    double copy          = 0;
    MeshWorker::mesh_loop(
      dof_handler.begin_active(),
      dof_handler.end(),
      [](const Iterator &, MeshWorker::ScratchData<dim> &, double &c) {
        c = 0;
      },
      [&](const double &c) { sum += c; },
      scratch,
      copy,
      flags,
      exact != nullptr ? BoundaryWorker(boundary_worker) : BoundaryWorker(),
      is_continuous ? FaceWorker<dim, double>() :
                      interface_worker<dim, double>(face_worker));
    return std::sqrt(sum);
  }



  template class System<2>;
  template class System<3>;
} // namespace ddfem::dg
