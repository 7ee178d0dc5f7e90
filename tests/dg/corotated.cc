// Corotated DG (stiffness warping, paper section 7), interior penalty and
// Babuska-Zlamal, FE_DGQ and FE_DGP, k = 1, 2, on a cube with hanging faces, mu
// = 1, lambda = 1.5, no loads. With R the element rotations fitted to u, the
// internal force is f(u) = K(R) u - F(R).
// - A rigid rotation Q by 70 degrees about (1, 2, 2)/3: the fitted
//   rotations are Q, and f = 0; the linear formulation gives a spurious
//   force. Without Dirichlet conditions, and with weak Dirichlet data equal
//   to the rotation on the x- face (all components prescribed).
// - A rigid rotation by 70 degrees about z on the sliding floor z = 0 (only
//   u_z = 0 prescribed, which the rotation satisfies): f = 0. Unwarped
//   Nitsche terms give the normal stress 2 lambda (cos 70 - 1) here.
// - Objectivity: for a non-uniform u with jumps between the cells (a twist
//   and a stretch, projected cellwise), f(Q (x + u) - x) = Q f(u), without
//   Dirichlet conditions, and with the x- face held at rest (weakly, all
//   components; rotated, its data are Q x - x), where u does not meet the
//   data, so that the Nitsche penalty acts. Not for
//   BZ, whose penalty is not warped (doc/dg.md): it is objective only where
//   the jumps vanish, as in the rigid motions above.

#include <deal.II/base/function.h>

#include <iostream>

#include "../tests.h"
#include "dg_tests.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  /// The rotation of the rigid motions: 70 degrees about (1, 2, 2)/3.
  Tensor<2, 3>
  rotation()
  {
    return testing::rotation_about(Tensor<1, 3>({1. / 3, 2. / 3, 2. / 3}), 70);
  }

  /// A twist about the z axis by 60 degrees per unit height, plus a
  /// stretch: u = R_z(60 z) x + (0.05 x^2, 0, 0.1 z^2) - x.
  class Twisted : public Function<3>
  {
  public:
    Twisted()
      : Function<3>(3)
    {}

    double
    value(const Point<3> &p, const unsigned int c) const override
    {
      const Tensor<1, 3> y =
        testing::rotation_about(Tensor<1, 3>({0, 0, 1}), 60 * p[2]) * p +
        Tensor<1, 3>({0.05 * p[0] * p[0], 0, 0.1 * p[2] * p[2]});
      return y[c] - p[c];
    }
  };
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Triangulation<3>                         tria;
  testing::make_cube_with_hanging_faces(tria);
  const Tensor<2, 3> Q   = rotation();
  const Tensor<2, 3> Q_z = testing::rotation_about(Tensor<1, 3>({0, 0, 1}), 70);
  const dg::ProblemData<3> free    = testing::uniform_data(tria, {1, 1.5});
  dg::ProblemData<3>       clamped = free;
  clamped.dirichlet =
    [&](const Point<3> &x, const unsigned int c, double, double &v) {
      v = (Q * x - x)[c];
      return x[0] < 1e-12;
    };
  // The x- face held at rest: rotated by Q, its data are those of clamped.
  dg::ProblemData<3> fixed = free;
  fixed.dirichlet =
    [](const Point<3> &x, const unsigned int, double, double &v) {
      v = 0;
      return x[0] < 1e-12;
    };
  dg::ProblemData<3> sliding = free;
  sliding.dirichlet =
    [](const Point<3> &x, const unsigned int c, double, double &v) {
      v = 0;
      return c == 2 && x[2] < 1e-12;
    };

  std::vector<dg::Parameters> variants =
    testing::interior_penalty_variants(dg::Parameters::Formulation::corotated);
  for (dg::Parameters p : testing::interior_penalty_variants(
         dg::Parameters::Formulation::corotated))
    {
      p.flux = dg::Parameters::Flux::babuska_zlamal;
      variants.push_back(p);
    }

  for (const dg::Parameters &p : variants)
    {
      const auto fe = p.make_element<3>();
      std::cout << testing::describe(p) << ":\n";

      // The rigid rotation, without and with Dirichlet conditions.
      for (const dg::ProblemData<3> *data :
           {&free, static_cast<const dg::ProblemData<3> *>(&clamped)})
        {
          dg::System<3>        system(tria, *fe, 3, p, *data);
          const Vector<double> u =
            testing::cellwise_affine(system, [&](const auto &) { return Q; });
          std::cout << (data == &free ? "  free" : "  x- face clamped")
                    << ", rigid rotation:\n    ";
          if (data == &free)
            {
              double rotation_error = 0;
              for (const Tensor<2, 3> &R : system.rotations(u))
                rotation_error = testing::worst(rotation_error, (R - Q).norm());
              testing::check_below("fitted rotation error",
                                   rotation_error,
                                   1e-12);
              std::cout << "    ";
            }
          system.assemble(10, 1, &u);
          testing::check_below("corotated |force| / (|K| |u|)",
                               testing::relative_force(system, u),
                               1e-12);
          system.assemble(10, 1);
          const double linear_force = testing::relative_force(system, u);
          std::cout << "    linear |force| / (|K| |u|) " << std::setprecision(2)
                    << linear_force << std::setprecision(6)
                    << " > 1e-3: " << (linear_force > 1e-3 ? "yes" : "NO")
                    << std::endl;
        }

      // A rotation about the normal of a sliding floor.
      {
        dg::System<3>        system(tria, *fe, 3, p, sliding);
        const Vector<double> u =
          testing::cellwise_affine(system, [&](const auto &) { return Q_z; });
        system.assemble(10, 1, &u);
        std::cout << "  sliding floor, rigid rotation about z:\n    ";
        testing::check_below("corotated |force| / (|K| |u|)",
                             testing::relative_force(system, u),
                             1e-12);
      }

      // Objectivity, without Dirichlet conditions and with the x- face held
      // at rest, whose rotated data are clamped's.
      if (p.flux == dg::Parameters::Flux::interior_penalty)
        for (const auto &[data, rotated_data, label] :
             {std::tuple(&free, &free, "free"),
              std::tuple(&std::as_const(fixed),
                         &std::as_const(clamped),
                         "x- face held")})
          {
            dg::System<3> system(tria, *fe, 3, p, *data),
              rotated(tria, *fe, 3, p, *rotated_data);
            Vector<double> u, x, force(system.dof_handler.n_dofs()),
              rotated_force(force.size());
            system.project_locally(Twisted(), u);
            system.project_locally(Functions::IdentityFunction<3>(), x);
            Vector<double> u_rotated = x;
            u_rotated += u;
            u_rotated =
              testing::transform_blocks(system, u_rotated, [&](const auto &) {
                return Q;
              });
            u_rotated -= x;
            system.assemble(10, 1, &u);
            system.matrix.vmult(force, u);
            force -= system.rhs;
            rotated.assemble(10, 1, &u_rotated);
            rotated.matrix.vmult(rotated_force, u_rotated);
            rotated_force -= rotated.rhs;
            rotated_force -=
              testing::transform_blocks(system, force, [&](const auto &) {
                return Q;
              });
            std::cout << "  objectivity, " << label << ", |[u]| / |u| > 1e-6: "
                      << (system.jump_norm(u) > 1e-6 * u.l2_norm() ? "yes" :
                                                                     "NO")
                      << "\n    ";
            testing::check_below("|f(Q (x + u) - x) - Q f(u)| / |f(u)|",
                                 rotated_force.l2_norm() / force.l2_norm(),
                                 1e-12);
          }
    }
}
