// The fine solver against a manufactured solution: on the unit cube,
// clamped on all six faces, the body force of the linear-elastic field
// u = delta (phi, phi, phi), phi = sin(pi x) sin(pi y) sin(pi z), which
// vanishes on the boundary:
//   b_i = delta pi^2 [3 mu phi + (lambda + mu) (phi - sum_{j != i} d_i d_j
//         phi / pi^2)],
// the negative divergence of the linear stress lambda tr(eps) I + 2 mu eps.
// At delta = 1e-6 the Neo-Hookean solution differs from the linear one by
// O(delta^2), far below the discretization error, so the L2 error of the
// FE_Q(p) solution must fall like h^(p+1) under grid refinement. This tests
// the assembly (body force, quadrature, Dirichlet data) on a field that is
// not affine, against a known answer.

#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/numerics/vector_tools.h>

#include <cmath>

#include "../tests.h"

using namespace ddfem;
using namespace dealii;

namespace
{
  const double delta = 1e-6;

  /// The manufactured displacement delta (phi, phi, phi).
  class Exact : public Function<3>
  {
  public:
    Exact()
      : Function<3>(3)
    {}

    double
    value(const Point<3> &p, const unsigned int) const override
    {
      return delta * std::sin(numbers::PI * p[0]) *
             std::sin(numbers::PI * p[1]) * std::sin(numbers::PI * p[2]);
    }
  };

  /// The body force's muparser expression of component @p i for the
  /// Lame constants @p mu and @p lambda.
  std::string
  body_force(const unsigned int i, const double mu, const double lambda)
  {
    const std::array<std::string, 3> s = {{"sin(pi*x)",
                                           "sin(pi*y)",
                                           "sin(pi*z)"}},
                                     c = {
                                       {"cos(pi*x)", "cos(pi*y)", "cos(pi*z)"}};
    const std::string phi = s[0] + "*" + s[1] + "*" + s[2];
    std::string       mixed;
    for (unsigned int j = 0; j < 3; ++j)
      if (j != i)
        {
          // d_i d_j phi / pi^2: cosines in i and j, the sine in the third.
          const unsigned int k = 3 - i - j;
          mixed += " - " + c[i] + "*" + c[j] + "*" + s[k];
        }
    return Utilities::to_string(delta) + "*pi^2*(" +
           Utilities::to_string(3 * mu) + "*" + phi + " + " +
           Utilities::to_string(lambda + mu) + "*(" + phi + mixed + "))";
  }

  /// The L2 error of the FE_Q(@p degree) solution on @p n^3 voxels.
  double
  l2_error(const unsigned int degree, const unsigned int n)
  {
    const double E = 1e6, nu = 0.3;
    const double mu     = E / (2 * (1 + nu)),
                 lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    std::string conditions;
    for (unsigned int f = 0; f < 6; ++f)
      conditions +=
        "subsection Condition " + std::to_string(f + 1) +
        "\n  set Type = fixed\n  set Region = " + std::string(1, "xyz"[f / 2]) +
        (f % 2 ? "+" : "-") + "\nend\n";
    testing::Problem problem(
      "subsection Geometry\n  set Grid size = " + std::to_string(n) + ", " +
      std::to_string(n) + ", " + std::to_string(n) +
      "\n  set Voxel size = " + Utilities::to_string(1. / n) +
      "\nend\n"
      "subsection Materials\n  set Palette = E=1e6 nu=0.3\nend\n"
      "subsection Discretization\n  set Polynomial degree = " +
      std::to_string(degree) +
      "\nend\n"
      "subsection Boundary conditions\n" +
      conditions +
      "end\n"
      "subsection Loads\n  set Body force = " +
      body_force(0, mu, lambda) + "; " + body_force(1, mu, lambda) + "; " +
      body_force(2, mu, lambda) +
      "\nend\n"
      "subsection Nonlinear solver\n  set Load steps = 1\n"
      "  set Newton tolerance = 1e-12\nend\n");
    AssertThrow(std::abs(problem.scene.palette[1].mu - mu) < 1e-9 * mu &&
                  std::abs(problem.scene.palette[1].lambda - lambda) <
                    1e-9 * lambda,
                ExcMessage("The palette's Lame constants differ."));
    AssertThrow(problem.solve().converged, ExcMessage("Not converged."));
    Vector<float> cell_errors(
      problem.discretization->triangulation.n_active_cells());
    VectorTools::integrate_difference(problem.discretization->mapping,
                                      problem.discretization->dof_handler,
                                      problem.solver->solution(),
                                      Exact(),
                                      cell_errors,
                                      QGauss<3>(degree + 2),
                                      VectorTools::L2_norm);
    return VectorTools::compute_global_error(
      problem.discretization->triangulation, cell_errors, VectorTools::L2_norm);
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  // ||u||_L2 = delta sqrt(3) / (2 sqrt(2)) on the unit cube.
  const double norm = delta * std::sqrt(3.) / (2 * std::sqrt(2.));
  for (const auto &[degree, grids] :
       {std::make_pair(1u, std::vector<unsigned int>{4, 8, 16}),
        std::make_pair(2u, std::vector<unsigned int>{2, 4, 8})})
    {
      std::cout << "FE_Q(" << degree << "), expected rate " << degree + 1
                << std::endl;
      double previous = 0;
      for (const unsigned int n : grids)
        {
          const double error = l2_error(degree, n) / norm;
          std::cout << "  " << n << "^3 voxels: relative L2 error "
                    << std::setprecision(3) << error;
          if (previous > 0)
            std::cout << ", rate " << std::setprecision(2)
                      << std::log2(previous / error);
          std::cout << std::setprecision(6) << std::endl;
          if (previous > 0)
            testing::check_below("    |rate - expected|",
                                 std::abs(std::log2(previous / error) -
                                          (degree + 1.)),
                                 0.25);
          previous = error;
        }
    }
}
