// The DG assembly (MeshWorker::mesh_loop over cells and faces) gives the
// same stiffness matrix and load vector bit for bit with one thread and with
// two, and so the same solution (doc/dg.md): a heterogeneous cantilever of
// 2 x 8 x 2 cells, FE_DGQ(2), both fluxes, linear and corotated (warped
// with the rotations of a twisted state), and a cube with hanging faces.

#include "../threads.h"

#include <deal.II/base/multithread_info.h>

#include <iostream>

#include "../tests.h"
#include "dg_tests.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  /// The matrix entries, then the load vector, then the solution of
  /// @p system assembled with @p threads threads (corotated about
  /// @p current if given) and solved.
  std::vector<double>
  assemble_and_solve(dg::System<3>        &system,
                     const unsigned int    threads,
                     const Vector<double> *current)
  {
    MultithreadInfo::set_thread_limit(threads);
    system.assemble(10, 1, current);
    system.solve();
    std::vector<double> numbers;
    for (const auto &entry : system.matrix)
      numbers.push_back(entry.value());
    numbers.insert(numbers.end(), system.rhs.begin(), system.rhs.end());
    numbers.insert(numbers.end(),
                   system.solution.begin(),
                   system.solution.end());
    return numbers;
  }

  /// Assembles and solves @p system with one thread and with two, and
  /// prints whether the numbers are identical.
  void
  compare(dg::System<3>        &system,
          const std::string    &name,
          const Vector<double> *current = nullptr)
  {
    const std::vector<double> one   = assemble_and_solve(system, 1, current);
    const unsigned int        n_one = MultithreadInfo::n_threads();
    const std::vector<double> two   = assemble_and_solve(system, 2, current);
    const unsigned int        n_two = MultithreadInfo::n_threads();
    std::cout << "  " << name << ", " << system.dof_handler.n_dofs()
              << " DoFs: " << n_one << " and " << n_two << " thread(s) "
              << (one == two ? "identical" : "DIFFERENT") << std::endl;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  std::cout << "Threads running a WorkStream with the limit 1: "
            << testing::threads_running(1)
            << ", with the limit 2: " << testing::threads_running(2)
            << std::endl;
  Triangulation<3> beam;
  testing::make_beam(beam, 2);
  dg::ProblemData<3> data = testing::cantilever_data(beam, {1, 1.5});
  for (const auto &cell : beam.active_cell_iterators())
    if (cell->center()[2] > 0.5)
      data.materials[cell->active_cell_index()] = {1e3, 1.5e3};

  std::cout << "Cantilever, FE_DGQ(2):" << std::endl;
  for (const auto flux : testing::dg_fluxes)
    {
      const dg::Parameters p =
        testing::dg_parameters(dg::Parameters::Element::dgq, 2, flux);
      const auto    fe = p.make_element<3>();
      dg::System<3> system(beam, *fe, 3, p, data);
      compare(system, testing::describe(p) + ", linear");
      // A twisted state about the beam's axis, for the corotated warping.
      const Vector<double> twisted = testing::cellwise_affine(
        system, [](const DoFHandler<3>::active_cell_iterator &cell) {
          return testing::rotation_about(Tensor<1, 3>({0, 1, 0}),
                                         10 * cell->center()[1]);
        });
      compare(system, testing::describe(p) + ", corotated", &twisted);
    }

  std::cout << "Cube with hanging faces, FE_DGP(1):" << std::endl;
  Triangulation<3> cube;
  testing::make_cube_with_hanging_faces(cube);
  dg::ProblemData<3> clamped = testing::uniform_data(cube, {1, 1.5});
  clamped.dirichlet = [](const Point<3> &p, unsigned int, double, double &v) {
    v = 0;
    return p[0] < 1e-12;
  };
  clamped.body_force = [](const Point<3> &p) {
    return Tensor<1, 3>({0, 0, -1 - p[0]});
  };
  const dg::Parameters p =
    testing::dg_parameters(dg::Parameters::Element::dgp,
                           1,
                           dg::Parameters::Flux::interior_penalty);
  const auto    fe = p.make_element<3>();
  dg::System<3> system(cube, *fe, 3, p, clamped);
  compare(system, testing::describe(p));
}
