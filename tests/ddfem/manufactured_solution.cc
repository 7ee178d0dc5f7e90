// The fine solver against a manufactured solution: on the unit cube,
// clamped on all six faces, the displacement u = delta (phi, phi, phi),
// phi = sin(pi x) sin(pi y) sin(pi z), which vanishes on the boundary, is
// the exact solution under the body force b = -Div P(F) of the Neo-Hookean
// material, P = mu F + (lambda ln J - mu) F^{-T}. F = I + a g^T (a =
// delta (1, 1, 1), g = grad phi) is a rank-one update, so J = 1 + a.g,
// F^{-T} = I - g a^T / J, and with H the Hessian of phi, t_i = delta sum_k
// H_ki and T = sum_i t_i,
//   b_i = 3 mu delta pi^2 phi - (lambda + mu - lambda ln J)
//         (t_i / J - delta g_i T / J^2),
// which for small delta is the body force of linear elasticity. Two
// amplitudes: delta = 1e-6, where the solution is linear-elastic, and
// delta = 0.1, where J ranges over [0.64, 1.36] (finite strain). The L2
// error of the FE_Q(p) solution must fall like h^(p+1) under grid
// refinement in both. This tests the assembly (body force, quadrature,
// Dirichlet data) and the nonlinear material on fields that are not
// affine, against a known answer.

#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/numerics/vector_tools.h>

#include <cmath>

#include "../tests.h"

using namespace ddfem;
using namespace dealii;

namespace
{
  /// The manufactured displacement delta (phi, phi, phi).
  class Exact : public Function<3>
  {
  public:
    explicit Exact(const double delta)
      : Function<3>(3)
      , delta(delta)
    {}

    double
    value(const Point<3> &p, const unsigned int) const override
    {
      return delta * std::sin(numbers::PI * p[0]) *
             std::sin(numbers::PI * p[1]) * std::sin(numbers::PI * p[2]);
    }

  private:
    const double delta;
  };

  /// The body force's muparser expression of component @p i for the
  /// amplitude @p delta and the Lame constants @p mu and @p lambda.
  std::string
  body_force(const unsigned int i,
             const double       delta,
             const double       mu,
             const double       lambda)
  {
    const std::array<std::string, 3> s = {{"sin(pi*x)",
                                           "sin(pi*y)",
                                           "sin(pi*z)"}},
                                     c = {
                                       {"cos(pi*x)", "cos(pi*y)", "cos(pi*z)"}};
    const std::string phi = "(" + s[0] + "*" + s[1] + "*" + s[2] + ")";
    const std::string d   = Utilities::to_string(delta);
    // g_j = d_j phi, and t_j = delta sum_k H_kj = delta pi^2 (-phi + sum
    // over k != j of cosines in j and k times the sine in the third).
    std::array<std::string, 3> g, t;
    for (unsigned int j = 0; j < 3; ++j)
      {
        g[j] =
          "(pi*" + c[j] + "*" + s[(j + 1) % 3] + "*" + s[(j + 2) % 3] + ")";
        t[j] = "(" + d + "*pi^2*(-" + phi;
        for (unsigned int k = 0; k < 3; ++k)
          if (k != j)
            t[j] += " + " + c[j] + "*" + c[k] + "*" + s[3 - j - k];
        t[j] += "))";
      }
    const std::string J =
      "(1 + " + d + "*(" + g[0] + " + " + g[1] + " + " + g[2] + "))";
    const std::string T = "(" + t[0] + " + " + t[1] + " + " + t[2] + ")";
    return Utilities::to_string(3 * mu) + "*" + d + "*pi^2*" + phi + " - (" +
           Utilities::to_string(lambda + mu) + " - " +
           Utilities::to_string(lambda) + "*ln(" + J + "))*(" + t[i] + "/" + J +
           " - " + d + "*" + g[i] + "*" + T + "/" + J + "^2)";
  }

  /// The L2 error of the FE_Q(@p degree) solution of amplitude @p delta
  /// on @p n^3 voxels, reached in @p load_steps load steps.
  double
  l2_error(const double       delta,
           const unsigned int degree,
           const unsigned int n,
           const unsigned int load_steps)
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
      body_force(0, delta, mu, lambda) + "; " +
      body_force(1, delta, mu, lambda) + "; " +
      body_force(2, delta, mu, lambda) +
      "\nend\n"
      "subsection Nonlinear solver\n  set Load steps = " +
      std::to_string(load_steps) +
      "\n"
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
                                      Exact(delta),
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
  for (const auto &[delta, load_steps] :
       {std::make_pair(1e-6, 1u), std::make_pair(0.1, 4u)})
    {
      // ||u||_L2 = delta sqrt(3) / (2 sqrt(2)) on the unit cube.
      const double norm = delta * std::sqrt(3.) / (2 * std::sqrt(2.));
      std::cout << "delta = " << delta << ", " << load_steps << " load step(s)"
                << std::endl;
      for (const auto &[degree, grids] :
           {std::make_pair(1u, std::vector<unsigned int>{4, 8, 16}),
            std::make_pair(2u, std::vector<unsigned int>{2, 4, 8})})
        {
          std::cout << "FE_Q(" << degree << "), expected rate " << degree + 1
                    << std::endl;
          double previous = 0;
          for (const unsigned int n : grids)
            {
              const double error =
                l2_error(delta, degree, n, load_steps) / norm;
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
                                     0.1);
              previous = error;
            }
        }
    }
}
