// Nitsche's penalty on faces inside a weakly held Dirichlet region
// (ProblemData::dirichlet_inside) scales with the whole face, also on the
// coarse side of a hanging face.
//
// Every component is held at 0 everywhere. A constant displacement c has
// no strain and no jumps, so its energy u^T K u is the Nitsche penalty
// alone: on every face F of every cell K, eta 2|F|/|K| times the integral
// of 2 mu |c|^2 + lambda (c.n)^2 over F. The two faces normal to axis d of
// a box with sides h_d have |F| = |K| / h_d, so
//   u^T K u = eta sum_K sum_d 4 |K| / h_d^2 (2 mu |c|^2 + lambda c_d^2)
// on any mesh of boxes, hanging faces or not. The boxes here have sides
// 1:2:4, so each direction's faces carry another weight. The coarse side
// of a hanging face used to weigh each subface by its own area, a quarter
// of the face's penalty in 3D.

#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/numerics/vector_tools.h>

#include <ddfem/dg/system.h>

#include <iostream>

#include "../tests.h"
#include "dg_tests.h"

using namespace dealii;
using namespace ddfem;

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const double                             mu = 1, lambda = 1.5, eta = 10;
  const Tensor<1, 3>                       c({1, -2, 0.5});
  const Functions::ConstantFunction<3>     constant(
    std::vector<double>{c[0], c[1], c[2]});

  for (const bool hanging : {false, true})
    {
      Triangulation<3> tria;
      GridGenerator::subdivided_hyper_rectangle(tria,
                                                {2, 2, 2},
                                                Point<3>(0, 0, 0),
                                                Point<3>(1, 2, 4));
      if (hanging)
        {
          tria.begin_active()->set_refine_flag();
          tria.execute_coarsening_and_refinement();
        }
      double expected = 0;
      for (const auto &cell : tria.active_cell_iterators())
        for (unsigned int d = 0; d < 3; ++d)
          expected += eta * 4 * cell->measure() /
                      std::pow(cell->extent_in_direction(d), 2) *
                      (2 * mu * c.norm_square() + lambda * c[d] * c[d]);
      std::cout << (hanging ? "With" : "Without")
                << " hanging faces: " << tria.n_active_cells()
                << " cells, expected u^T K u = " << expected << std::endl;

      dg::ProblemData<3> data = testing::uniform_data(tria, {mu, lambda});
      data.dirichlet = [](const Point<3> &, unsigned int, double, double &v) {
        v = 0;
        return true;
      };
      data.dirichlet_inside = true;
      for (const auto element : testing::dg_elements)
        for (const unsigned int degree : {1u, 2u})
          for (const auto flux : testing::dg_fluxes)
            {
              dg::Parameters p = testing::dg_parameters(element, degree, flux);
              p.dirichlet      = dg::Parameters::Dirichlet::weak;
              const auto    fe = p.make_element<3>();
              dg::System<3> system(tria, *fe, 3, p, data);
              system.assemble(eta, 1);
              // Constants are in every element's space, so the projection
              // is exact up to its solver's tolerance.
              AffineConstraints<double> none;
              none.close();
              Vector<double> u(system.dof_handler.n_dofs());
              VectorTools::project(system.mapping,
                                   system.dof_handler,
                                   none,
                                   QGauss<3>(degree + 1),
                                   constant,
                                   u);
              const double energy = system.matrix.matrix_norm_square(u);
              std::cout << "  " << testing::describe(p) << ": ";
              testing::check_below("relative deviation of u^T K u",
                                   std::abs(energy - expected) / expected,
                                   1e-10);
            }
    }
}
