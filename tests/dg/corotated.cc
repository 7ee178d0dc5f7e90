// Corotated DG (stiffness warping, paper section 7): a large rigid
// rotation of a stress-free body must produce zero internal force
// K(R) u - F(R) with the element rotations R fitted to u, whereas linear
// elasticity produces a spurious force. The fitted rotations must be the
// applied rotation. IP flux, no loads, no Dirichlet conditions.

#include <deal.II/base/function.h>

#include <iostream>

#include "../tests.h"
#include "dg_tests.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  /// u = (Q - I) x for the rotation Q by 70 degrees about (1, 2, 2)/3.
  Tensor<2, 3>
  rotation()
  {
    const Tensor<1, 3> k({1. / 3, 2. / 3, 2. / 3});
    const double       a = 70 * numbers::PI / 180;
    Tensor<2, 3>       K;
    K[0][1] = -k[2];
    K[0][2] = k[1];
    K[1][0] = k[2];
    K[1][2] = -k[0];
    K[2][0] = -k[1];
    K[2][1] = k[0];
    return unit_symmetric_tensor<3>() + std::sin(a) * K +
           (1 - std::cos(a)) * K * K;
  }

  class Rotated : public Function<3>
  {
  public:
    Rotated()
      : Function<3>(3)
      , Q(rotation())
    {}

    double
    value(const Point<3> &p, const unsigned int c) const override
    {
      return (Q * p - p)[c];
    }

  private:
    const Tensor<2, 3> Q;
  };
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Triangulation<3>                         tria;
  testing::make_cube_with_hanging_faces(tria);
  const dg::ProblemData<3> data = testing::uniform_data(tria, {1, 1.5});

  for (const auto element : testing::dg_elements)
    for (const unsigned int degree : {1u, 2u})
      {
        dg::Parameters p =
          testing::dg_parameters(element,
                                 degree,
                                 dg::Parameters::Flux::interior_penalty);
        p.formulation     = dg::Parameters::Formulation::corotated;
        const auto     fe = p.make_element<3>();
        dg::System<3>  system(tria, *fe, 3, p, data);
        Vector<double> u;
        system.project_locally(Rotated(), u);
        double rotation_error = 0;
        for (const Tensor<2, 3> &R : system.rotations(u))
          rotation_error = std::max(rotation_error, (R - rotation()).norm());
        std::cout << testing::describe(p) << ":\n  ";
        testing::check_below("fitted rotation error", rotation_error, 1e-12);

        Vector<double> force(u.size());
        system.assemble(10, 1, &u);
        const double scale = system.matrix.linfty_norm() * u.l2_norm();
        system.matrix.vmult(force, u);
        force -= system.rhs;
        std::cout << "  ";
        testing::check_below("corotated |force| / (|K| |u|)",
                             force.l2_norm() / scale,
                             1e-12);
        system.assemble(10, 1);
        system.matrix.vmult(force, u);
        std::cout << "  linear |force| / (|K| |u|) > 1e-3: "
                  << (force.l2_norm() / scale > 1e-3 ? "yes" : "NO")
                  << std::endl;
      }
}
