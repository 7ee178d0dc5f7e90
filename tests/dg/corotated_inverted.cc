// The element rotation of the corotated formulation when the fitted affine
// map A does not preserve orientation: u = A x - x on every cell with
// A = Q D, Q a rotation by 70 degrees about (1, 2, 2)/3 and D one of
// diag(1.2, 0.9, -0.3), diag(-0.3, 0.9, 1.2) (inverted cells, det A < 0)
// and diag(1.2, 0.9, 0) (flattened, det A = 0). The rotation must be the
// rotation closest to A, here Q: a proper rotation (det +1), not the
// reflection Q diag(1, 1, -1) that the orthogonal polar factor of an
// inverted map is, and defined for a flattened one.

#include <iostream>

#include "../tests.h"
#include "dg_tests.h"

using namespace dealii;
using namespace ddfem;

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Triangulation<3>                         tria;
  testing::make_cube_with_hanging_faces(tria);
  const dg::ProblemData<3> data = testing::uniform_data(tria, {1, 1.5});
  const Tensor<2, 3>       Q =
    testing::rotation_about(Tensor<1, 3>({1. / 3, 2. / 3, 2. / 3}), 70);

  for (dg::Parameters p : testing::interior_penalty_variants(
         dg::Parameters::Formulation::corotated))
    {
      const auto    fe = p.make_element<3>();
      dg::System<3> system(tria, *fe, 3, p, data);
      std::cout << testing::describe(p) << ":\n";
      for (const Tensor<1, 3> &diagonal : {Tensor<1, 3>({1.2, 0.9, -0.3}),
                                           Tensor<1, 3>({-0.3, 0.9, 1.2}),
                                           Tensor<1, 3>({1.2, 0.9, 0})})
        {
          Tensor<2, 3> A;
          for (unsigned int d = 0; d < 3; ++d)
            for (unsigned int e = 0; e < 3; ++e)
              A[d][e] = Q[d][e] * diagonal[e];
          const Vector<double> u =
            testing::cellwise_affine(system, [&](const auto &) { return A; });
          double error = 0, det_error = 0;
          for (const Tensor<2, 3> &R : system.rotations(u))
            {
              error = testing::worst(error, (R - Q).norm());
              det_error =
                testing::worst(det_error, std::abs(determinant(R) - 1));
            }
          std::cout << "  D = diag(" << diagonal << "): ";
          testing::check_below("|R - Q|", error, 1e-12);
          std::cout << "    ";
          testing::check_below("|det R - 1|", det_error, 1e-12);
        }
    }
}
