// Rigid body motions (a translation plus an infinitesimal rotation) lie in
// the local spaces of FE_DGQ(k) and FE_DGP(k), k >= 1: they must give zero
// strain energy u^T K u for both fluxes and zero jumps, also across hanging
// faces. A stretch must give positive energy, so the check can fail.

#include <deal.II/base/function.h>

#include <iostream>

#include "../tests.h"
#include "dg_tests.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  /// u = a + w x x, or a stretch (1e-3 x, 0, 0) if @p stretch.
  class Motion : public Function<3>
  {
  public:
    explicit Motion(const bool stretch)
      : Function<3>(3)
      , stretch(stretch)
    {}

    double
    value(const Point<3> &p, const unsigned int c) const override
    {
      if (stretch)
        return c == 0 ? 1e-3 * p[0] : 0;
      const Tensor<1, 3> a({0.1, -0.2, 0.3});
      const Tensor<1, 3> w({0.02, 0.05, -0.03});
      return (a + cross_product_3d(w, p))[c];
    }

  private:
    const bool stretch;
  };
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Triangulation<3>                         tria;
  testing::make_cube_with_hanging_faces(tria);
  const dg::ProblemData<3> data = testing::uniform_data(tria, {1e6, 2e6});

  for (const auto element : testing::dg_elements)
    for (const unsigned int degree : {1u, 2u})
      for (const auto flux : testing::dg_fluxes)
        {
          const dg::Parameters p =
            testing::dg_parameters(element, degree, flux);
          const auto    fe = p.make_element<3>();
          dg::System<3> system(tria, *fe, 3, p, data);
          system.assemble(10, 1);
          const double   scale = system.matrix.linfty_norm();
          Vector<double> u;
          system.project_locally(Motion(false), u);
          std::cout << testing::describe(p) << ": ";
          testing::check_below("rigid energy / (|K| |u|^2)",
                               system.matrix.matrix_norm_square(u) /
                                 (scale * u.norm_sqr()),
                               1e-13);
          // The jumps do not depend on the flux: checked once.
          if (flux == testing::dg_fluxes[0])
            {
              std::cout << "  ";
              testing::check_below("rigid jump / |u|",
                                   system.jump_norm(u) / u.l2_norm(),
                                   1e-13);
            }
          system.project_locally(Motion(true), u);
          std::cout << "  stretch energy / (|K| |u|^2) > 1e-6: "
                    << (system.matrix.matrix_norm_square(u) /
                              (scale * u.norm_sqr()) >
                            1e-6 ?
                          "yes" :
                          "NO")
                    << std::endl;
        }
}
