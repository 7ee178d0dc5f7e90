// Very thin elements, aspect ratio 1:50: a cantilever strip 1 x 0.5 x
// 0.002 of 10 x 5 x 1 cells (0.1 x 0.1 x 0.002 each), nu = 0, loaded by a
// shear traction at its free end. The automatic penalty of IP must end
// positive definite (eq. 7 scales the penalty with area/volume, i.e. with
// the inverse cell size across each face). BZ needs a fixed penalty: eta =
// 10 and 100, the paper's range, whose O(1/eta) error the ratios show.
// Deflections are given relative to the Euler-Bernoulli value
// 4 q L^3 / (E t^2); low-order elements lock in shear on such cells, which
// the ratios show.

#include <deal.II/fe/fe_q.h>

#include <iostream>

#include "../tests.h"
#include "dg_tests.h"

using namespace dealii;
using namespace ddfem;

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const double                             L = 1, t = 0.002, E = 1e9, q = 1;
  Triangulation<3>                         tria;
  GridGenerator::subdivided_hyper_rectangle(tria,
                                            {10, 5, 1},
                                            Point<3>(0, 0, 0),
                                            Point<3>(L, 0.5, t));
  dg::ProblemData<3> data = testing::uniform_data(tria, {E / 2, 0});
  data.dirichlet = [](const Point<3> &x, unsigned int, double, double &v) {
    v = 0;
    return x[0] < 1e-12;
  };
  data.traction =
    [&](const Point<3> &, const Point<3> &x, const Tensor<1, 3> &) {
      return x[0] > L - 1e-12 ? Tensor<1, 3>({0, 0, -q}) : Tensor<1, 3>();
    };
  const double beam = 4 * q * L * L * L / (E * t * t);

  dg::Parameters cg;
  cg.dirichlet = dg::Parameters::Dirichlet::strong;
  std::cout << std::setprecision(4);
  const auto report = [&](const std::string      &name,
                          const FiniteElement<3> &fe,
                          const dg::Parameters   &p) {
    dg::System<3>          system(tria, fe, 3, p, data);
    const dg::Definiteness d = system.settle_penalty(1);
    system.solve();
    std::cout << std::left << std::setw(14) << name << std::right
              << " deflection / beam theory " << std::setw(7)
              << -testing::tip_deflection(system, Point<3>(L, 0.25, t / 2)) /
                   beam;
    if (!system.continuous())
      std::cout << ", eta " << system.penalty() << ", " << dg::to_string(d);
    std::cout << std::endl;
  };
  report("CG Q1", FE_Q<3>(1), cg);
  report("CG Q2", FE_Q<3>(2), cg);
  for (const unsigned int k : {1u, 2u})
    {
      dg::Parameters p;
      p.degree = k;
      report(testing::describe(p), *p.make_element<3>(), p);
    }
  for (const double eta : {10., 100.})
    for (const unsigned int k : {1u, 2u})
      {
        dg::Parameters p;
        p.flux    = dg::Parameters::Flux::babuska_zlamal;
        p.degree  = k;
        p.penalty = eta;
        report(testing::describe(p), *p.make_element<3>(), p);
      }
}
