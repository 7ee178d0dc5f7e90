// Consistency across a material interface: two materials, mu = 1,
// lambda = 1.5 below z = 0.5 and mu = 1e3, lambda = 2e3 above, and the
// 1D-strain solution u = c + (0, 0, u_z(z)) with u_z piecewise linear,
// kinked at z = 0.5 so that the normal stress (2 mu + lambda) u_z' is
// continuous there; no body force, exact Dirichlet data imposed weakly on
// the whole boundary. The interface runs through hanging faces. The
// symmetric interior penalty form must reproduce u to round-off (its
// average stress {sigma} n equals the continuous traction, and [u] = 0),
// for FE_DGQ and FE_DGP, k = 1, 2.

#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/numerics/vector_tools.h>

#include <iostream>

#include "../tests.h"
#include "dg_tests.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  const dg::CellMaterial soft = {1, 1.5}, stiff = {1e3, 2e3};

  /// The strain u_z' below and above the interface.
  constexpr double strain_below = 0.1;
  const double     strain_above =
    strain_below * (2 * soft.mu + soft.lambda) / (2 * stiff.mu + stiff.lambda);

  /// The exact solution.
  class Layered : public Function<3>
  {
  public:
    Layered()
      : Function<3>(3)
    {}

    double
    value(const Point<3> &p, const unsigned int c) const override
    {
      const Tensor<1, 3> translation({0.01, -0.02, 0.03});
      const double       z = p[2];
      return translation[c] + (c == 2 ? (z < 0.5 ? strain_below * z :
                                                   0.5 * strain_below +
                                                     strain_above * (z - 0.5)) :
                                        0);
    }
  };
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Triangulation<3>                         tria;
  testing::make_cube_with_hanging_faces(tria);
  dg::ProblemData<3> data = testing::uniform_data(tria, soft);
  for (const auto &cell : tria.active_cell_iterators())
    if (cell->center()[2] > 0.5)
      data.materials[cell->active_cell_index()] = stiff;
  const Layered exact;
  data.dirichlet =
    [&](const Point<3> &p, const unsigned int c, double, double &v) {
      v = exact.value(p, c);
      return true;
    };
  std::cout << "strain below " << strain_below << ", above " << strain_above
            << "; normal stress " << (2 * soft.mu + soft.lambda) * strain_below
            << " on both sides" << std::endl;

  for (dg::Parameters p :
       testing::interior_penalty_variants(dg::Parameters::Formulation::linear))
    {
      p.penalty        = 10;
      const auto    fe = p.make_element<3>();
      dg::System<3> system(tria, *fe, 3, p, data);
      system.settle_penalty(1);
      system.solve();
      Vector<float>        cellwise(tria.n_active_cells());
      const QGauss<3>      quadrature(p.degree + 2);
      const Vector<double> zero(system.dof_handler.n_dofs());
      // The L2 norm of f - v.
      const auto l2 = [&](const Function<3> &f, const Vector<double> &v) {
        VectorTools::integrate_difference(system.mapping,
                                          system.dof_handler,
                                          v,
                                          f,
                                          cellwise,
                                          quadrature,
                                          VectorTools::L2_norm);
        return VectorTools::compute_global_error(tria,
                                                 cellwise,
                                                 VectorTools::L2_norm);
      };
      std::cout << testing::describe(p) << ": ";
      testing::check_below("L2 error / |u|",
                           l2(exact, system.solution) / l2(exact, zero),
                           1e-10);
    }
}
