#ifndef ddfem_tests_dg_h
#define ddfem_tests_dg_h

// Helpers shared by the DG tests: small meshes, problem data and dense
// eigenvalues.

#include <deal.II/base/function.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/numerics/vector_tools.h>

#include <ddfem/dg/parameters.h>
#include <ddfem/dg/system.h>
#include <ddfem/solver/probe.h>

#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace ddfem::testing
{
  using namespace dealii;

  /// Both discontinuous elements, FE_DGQ and FE_DGP.
  constexpr std::array<dg::Parameters::Element, 2> dg_elements = {
    {dg::Parameters::Element::dgq, dg::Parameters::Element::dgp}};

  /// Both fluxes, interior penalty and Babuska-Zlamal.
  constexpr std::array<dg::Parameters::Flux, 2> dg_fluxes = {
    {dg::Parameters::Flux::interior_penalty,
     dg::Parameters::Flux::babuska_zlamal}};

  /// The eigenvalues, ascending, of the symmetric matrix @p K (overwritten)
  /// whose infinity norm is at most @p norm: by Gershgorin they all lie in
  /// [-norm, norm], the interval LAPACK searches (with a margin).
  inline Vector<double>
  symmetric_eigenvalues(LAPACKFullMatrix<double> &K, const double norm)
  {
    K.set_property(LAPACKSupport::symmetric);
    Vector<double>     eigenvalues;
    FullMatrix<double> eigenvectors;
    K.compute_eigenvalues_symmetric(
      -2 * norm, 2 * norm, 0., eigenvalues, eigenvectors);
    return eigenvalues;
  }

  /// The unit cube as 2 x 2 x 2 cells with the first one refined once, so
  /// that the mesh has hanging faces.
  inline void
  make_cube_with_hanging_faces(Triangulation<3> &tria)
  {
    GridGenerator::subdivided_hyper_cube(tria, 2, 0, 1);
    tria.begin_active()->set_refine_flag();
    tria.execute_coarsening_and_refinement();
  }

  /// The beam [0, 1] x [0, 4] x [0, 1] as @p n x 4n x @p n cells.
  inline void
  make_beam(Triangulation<3> &tria, const unsigned int n)
  {
    GridGenerator::subdivided_hyper_rectangle(tria,
                                              {n, 4 * n, n},
                                              Point<3>(0, 0, 0),
                                              Point<3>(1, 4, 1));
  }

  /// Problem data with the material @p m in every cell of @p tria, without
  /// loads and Dirichlet conditions.
  inline dg::ProblemData<3>
  uniform_data(const Triangulation<3> &tria, const dg::CellMaterial &m)
  {
    dg::ProblemData<3> data;
    data.materials.assign(tria.n_active_cells(), m);
    return data;
  }

  /// The cantilever on the beam of make_beam(): the material @p m in
  /// every cell, clamped on y = 0, the traction (0, 0, -1) on y = 4.
  inline dg::ProblemData<3>
  cantilever_data(const Triangulation<3> &tria, const dg::CellMaterial &m)
  {
    dg::ProblemData<3> data = uniform_data(tria, m);
    data.dirichlet = [](const Point<3> &x, unsigned int, double, double &v) {
      v = 0;
      return x[1] < 1e-12;
    };
    data.traction =
      [](const Point<3> &, const Point<3> &x, const Tensor<1, 3> &) {
        return x[1] > 4 - 1e-12 ? Tensor<1, 3>({0, 0, -1}) : Tensor<1, 3>();
      };
    return data;
  }

  /// The z displacement of the solution of @p system at @p tip, by default
  /// the middle of the free end of the beam of make_beam(): the mean over
  /// the cells that hold @p tip, as scene probes take it (the default tip
  /// lies on an edge of four cells, where DG has four values).
  inline double
  tip_deflection(const dg::System<3> &system,
                 const Point<3>      &tip = Point<3>(0.5, 4, 0.5))
  {
    return solver::probe_displacement(
      system.mapping, system.dof_handler, system.solution, tip)[2];
  }

  /// Default DG parameters but for @p element, @p degree and @p flux.
  inline dg::Parameters
  dg_parameters(const dg::Parameters::Element element,
                const unsigned int            degree,
                const dg::Parameters::Flux    flux)
  {
    dg::Parameters p;
    p.element = element;
    p.degree  = degree;
    p.flux    = flux;
    return p;
  }

  /// Default DG parameters with the interior penalty flux and
  /// @p formulation for every element type at degrees 1 and 2, element by
  /// element.
  inline std::vector<dg::Parameters>
  interior_penalty_variants(const dg::Parameters::Formulation formulation)
  {
    std::vector<dg::Parameters> variants;
    for (const auto element : dg_elements)
      for (const unsigned int degree : {1u, 2u})
        {
          variants.push_back(dg_parameters(
            element, degree, dg::Parameters::Flux::interior_penalty));
          variants.back().formulation = formulation;
        }
    return variants;
  }

  /**
   * The coefficients of the field A_K v on every cell K of @p system, for
   * the coefficients @p v of a vector field and A_K = @p A(K): the dim
   * coefficients of each scalar shape function are multiplied by A_K. With
   * v = X0, the coefficients of the identity map x, this is the affine map
   * A_K x, exactly, for FE_DGQ and FE_DGP alike.
   */
  inline Vector<double>
  transform_blocks(const dg::System<3>                             &system,
                   const Vector<double>                            &v,
                   const std::function<Tensor<2, 3>(
                     const DoFHandler<3>::active_cell_iterator &)> &A)
  {
    Vector<double>                       w(v.size());
    const FiniteElement<3>              &fe = system.fe;
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : system.dof_handler.active_cell_iterators())
      {
        const Tensor<2, 3> A_K = A(cell);
        cell->get_dof_indices(dofs);
        for (unsigned int i = 0; i < dofs.size(); ++i)
          {
            const auto [c, base] = fe.system_to_component_index(i);
            for (unsigned int a = 0; a < 3; ++a)
              w[dofs[i]] +=
                A_K[c][a] * v[dofs[fe.component_to_system_index(a, base)]];
          }
      }
    return w;
  }

  /**
   * The coefficients of the displacement u = A_K x - x on every cell K of
   * @p system, A_K = @p A(K).
   */
  inline Vector<double>
  cellwise_affine(const dg::System<3>                             &system,
                  const std::function<Tensor<2, 3>(
                    const DoFHandler<3>::active_cell_iterator &)> &A)
  {
    Vector<double> x;
    system.project_locally(Functions::IdentityFunction<3>(), x);
    Vector<double> u = transform_blocks(system, x, A);
    u -= x;
    return u;
  }

  /**
   * The internal force K u - F of @p system as last assembled, relative to
   * |K| |u| (max row sum norm of K, l2 norm of u).
   */
  inline double
  relative_force(const dg::System<3> &system, const Vector<double> &u)
  {
    Vector<double> force(u.size());
    system.matrix.vmult(force, u);
    force -= system.rhs;
    return force.l2_norm() / (system.matrix.linfty_norm() * u.l2_norm());
  }

  /// "IP FE_DGQ(1)" and the like.
  inline std::string
  describe(const dg::Parameters &p)
  {
    return std::string(
             p.flux == dg::Parameters::Flux::interior_penalty ? "IP" : "BZ") +
           " " + p.element_name() + "(" + std::to_string(p.degree) + ")";
  }
} // namespace ddfem::testing

#endif
