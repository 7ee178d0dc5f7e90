#ifndef ddfem_tests_dg_h
#define ddfem_tests_dg_h

// Helpers shared by the DG tests: small meshes and problem data.

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>
#include <deal.II/numerics/vector_tools.h>

#include <ddfem/dg/parameters.h>
#include <ddfem/dg/system.h>

#include <array>
#include <string>

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
  /// the middle of the free end of the beam of make_beam().
  inline double
  tip_deflection(const dg::System<3> &system,
                 const Point<3>      &tip = Point<3>(0.5, 4, 0.5))
  {
    Vector<double> value(3);
    VectorTools::point_value(
      system.mapping, system.dof_handler, system.solution, tip, value);
    return value[2];
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
