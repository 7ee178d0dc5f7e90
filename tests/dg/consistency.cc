// Consistency: with the interior penalty flux, an exact polynomial
// solution of degree <= k (with its load and Dirichlet data, weak or
// strong) is reproduced to round-off, on a mesh with hanging faces. The
// Babuska-Zlamal flux is inconsistent: its error stays well above that.

#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/numerics/vector_tools.h>

#include <ddfem/dg/studies.h>

#include <iostream>

#include "../tests.h"
#include "dg_tests.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  /// A vector polynomial of degree @p degree (1 or 2) with all terms.
  class Polynomial : public Function<3>
  {
  public:
    explicit Polynomial(const unsigned int degree)
      : Function<3>(3)
      , degree(degree)
    {}

    double
    value(const Point<3> &p, const unsigned int c) const override
    {
      double u = 0.1 * (c + 1) + 0.2 * p[0] - 0.1 * p[1] + 0.3 * c * p[2];
      if (degree == 2)
        u += quadratic(c) * p * p / 2;
      return u;
    }

    SymmetricTensor<2, 3>
    hessian(const Point<3> &, const unsigned int c) const override
    {
      return degree == 2 ? quadratic(c) : SymmetricTensor<2, 3>();
    }

  private:
    static SymmetricTensor<2, 3>
    quadratic(const unsigned int c)
    {
      SymmetricTensor<2, 3> Q;
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int j = i; j < 3; ++j)
          Q[i][j] = 0.1 * (1 + i + 2 * j + c) * (i == j ? 1 : 0.5);
      return Q;
    }

    const unsigned int degree;
  };
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Triangulation<3>                         tria;
  testing::make_cube_with_hanging_faces(tria);
  const double mu = 1, lambda = 1.5;

  for (const unsigned int degree : {1u, 2u})
    {
      const Polynomial   exact(degree);
      dg::ProblemData<3> data = testing::uniform_data(tria, {mu, lambda});
      data.body_force         = [&](const Point<3> &p) {
        return dg::manufactured_load(exact, p, mu, lambda);
      };
      data.dirichlet =
        [&](const Point<3> &p, const unsigned int c, double, double &v) {
          v = exact.value(p, c);
          return true;
        };
      for (const auto element : testing::dg_elements)
        for (const auto dirichlet : {dg::Parameters::Dirichlet::weak,
                                     dg::Parameters::Dirichlet::strong})
          for (const auto flux : testing::dg_fluxes)
            {
              if (element == dg::Parameters::Element::dgp &&
                  dirichlet == dg::Parameters::Dirichlet::strong)
                continue;
              dg::Parameters p = testing::dg_parameters(element, degree, flux);
              p.dirichlet      = dirichlet;
              p.penalty        = 10;
              const auto    fe = p.make_element<3>();
              dg::System<3> system(tria, *fe, 3, p, data);
              system.settle_penalty(1);
              system.solve();
              Vector<float> cellwise(tria.n_active_cells());
              VectorTools::integrate_difference(system.mapping,
                                                system.dof_handler,
                                                system.solution,
                                                exact,
                                                cellwise,
                                                QGauss<3>(degree + 2),
                                                VectorTools::L2_norm);
              const double error =
                VectorTools::compute_global_error(tria,
                                                  cellwise,
                                                  VectorTools::L2_norm);
              std::cout << "degree " << degree << " solution, "
                        << testing::describe(p) << ", "
                        << (dirichlet == dg::Parameters::Dirichlet::weak ?
                              "weak" :
                              "strong")
                        << ": ";
              if (flux == dg::Parameters::Flux::interior_penalty)
                testing::check_below("L2 error", error, 1e-10);
              else
                std::cout << "L2 error " << std::setprecision(2) << error
                          << std::setprecision(6)
                          << " > 1e-4: " << (error > 1e-4 ? "yes" : "NO")
                          << std::endl;
            }
    }
}
