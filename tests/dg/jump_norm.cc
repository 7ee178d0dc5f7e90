// The jump seminorm of System::jump_norm() on two unit squares side by side
// ([0,2] x [0,1]), whose values are known by hand. The weight of a face is
// the penalty's without eta: |F| (1/|K| + 1/|K'|) = 2 on the interior face
// x = 1, 2 |F| / |K| = 2 on each of the six boundary faces.
// - FE_DGQ(1), u = 1 on the left square and 0 on the right: the jump is 1
//   on the interior face, so J(u) = sqrt(2). Against the exact solution 0
//   the three boundary faces of the left square add 2 each: sqrt(8); against
//   1/2 all six add 2 / 4 each: sqrt(5).
// - FE_Q(1), u = x interpolated: no jumps. Against 0 the traces count:
//   2 (|2|^2 on x = 2) + 2 (int_0^2 x^2 dx on y = 0 and y = 1, twice) =
//   8 + 32/3, so J = sqrt(56/3); against x itself 0.

#include <deal.II/base/function.h>
#include <deal.II/fe/fe_dgq.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/numerics/vector_tools.h>

#include <ddfem/dg/system.h>

#include <iomanip>
#include <iostream>

#include "../tests.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  /// 1 left of x = 1, 0 right of it.
  class Step : public Function<2>
  {
  public:
    double
    value(const Point<2> &p, const unsigned int) const override
    {
      return p[0] < 1 ? 1 : 0;
    }
  };

  /// u = x.
  class Ramp : public Function<2>
  {
  public:
    double
    value(const Point<2> &p, const unsigned int) const override
    {
      return p[0];
    }
  };
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Triangulation<2>                         tria;
  GridGenerator::subdivided_hyper_rectangle(tria,
                                            {2, 1},
                                            Point<2>(0, 0),
                                            Point<2>(2, 1));
  dg::ProblemData<2> data;
  data.materials.assign(tria.n_active_cells(), {1, 0});
  std::cout << std::setprecision(15);
  const Functions::ZeroFunction<2>     zero;
  const Functions::ConstantFunction<2> half(0.5);
  const Ramp                           ramp;

  {
    const FE_DGQ<2>      fe(1);
    const dg::Parameters p;
    dg::System<2>        system(tria, fe, 1, p, data);
    Vector<double>       u;
    system.project_locally(Step(), u);
    std::cout << "FE_DGQ(1), a step: J(u) = " << system.jump_norm(u)
              << " (sqrt(2)), J(u - 0) = " << system.jump_norm(u, &zero)
              << " (sqrt(8)), J(u - 1/2) = " << system.jump_norm(u, &half)
              << " (sqrt(5))" << std::endl;
  }
  {
    const FE_Q<2>        fe(1);
    const dg::Parameters p;
    dg::System<2>        system(tria, fe, 1, p, data);
    Vector<double>       u(system.dof_handler.n_dofs());
    VectorTools::interpolate(system.mapping, system.dof_handler, ramp, u);
    std::cout << "FE_Q(1), u = x: J(u) = " << system.jump_norm(u)
              << " (0), J(u - 0) = " << system.jump_norm(u, &zero) << " ("
              << std::sqrt(56. / 3)
              << "), J(u - x) = " << system.jump_norm(u, &ramp) << " (0)"
              << std::endl;
  }
}
