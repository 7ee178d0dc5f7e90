// The stiffness matrix is symmetric for both fluxes, also corotated with a
// different rotation in every cell (pseudo-random axes and angles of 5 to
// 175 degrees, which the fitted rotations must reproduce); the
// Babuska-Zlamal matrix is positive definite for any penalty > 0; the
// interior penalty matrix is not for a too small penalty, and the
// automatic penalty (start at 1, double) ends positive definite; with BZ it
// is rejected (it would always stop at eta = 1). A cube clamped weakly on
// its x- face, with hanging faces. Every definiteness verdict of
// System::check_definiteness() (sparse Cholesky) is compared with the sign
// of the smallest eigenvalue of the dense matrix (LAPACK dsyevx). A matrix
// that is singular in exact arithmetic can pass Cholesky in floating point
// with a pivot at round-off level; the check must reject it (one square of
// the 2D Poisson problem at eta = 1).

#include <deal.II/base/function.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <iomanip>
#include <iostream>

#include "../tests.h"
#include "dg_tests.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  /// max |K - K^T| / max |K|.
  double
  asymmetry(const SparseMatrix<double> &K)
  {
    double a = 0;
    for (unsigned int i = 0; i < K.m(); ++i)
      for (auto e = K.begin(i); e != K.end(i); ++e)
        a = testing::worst(a, std::abs(e->value() - K.el(e->column(), i)));
    return a / K.linfty_norm();
  }

  /// System::check_definiteness() of @p system, and whether the smallest
  /// eigenvalue of the dense matrix has the sign that verdict implies.
  std::string
  definiteness(dg::System<3> &system)
  {
    const SparseMatrix<double> &K = system.matrix;
    LAPACKFullMatrix<double>    dense(K.m());
    dense = K;
    const Vector<double> eigenvalues =
      testing::symmetric_eigenvalues(dense, K.linfty_norm());
    const dg::Definiteness verdict  = system.check_definiteness();
    const bool             positive = eigenvalues(0) > 0;
    const bool             agrees =
      positive == (verdict == dg::Definiteness::positive_definite);
    return dg::to_string(verdict) + (agrees ?
                                       " (the smallest eigenvalue agrees)" :
                                       " (the smallest eigenvalue DISAGREES)");
  }

  /// A rotation per cell, pseudo-random: axis and angle from its index.
  Tensor<2, 3>
  cell_rotation(const DoFHandler<3>::active_cell_iterator &cell)
  {
    const double       i = cell->active_cell_index();
    const Tensor<1, 3> axis(
      {std::sin(1 + 2 * i), std::cos(3 + 5 * i), std::sin(0.5 + 7 * i)});
    return testing::rotation_about(axis / axis.norm(),
                                   5 + 170 * std::abs(std::sin(1 + 11 * i)));
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Triangulation<3>                         tria;
  testing::make_cube_with_hanging_faces(tria);
  dg::ProblemData<3> data = testing::uniform_data(tria, {1, 1.5});
  for (const auto &cell : tria.active_cell_iterators())
    if (cell->center()[2] > 0.5)
      data.materials[cell->active_cell_index()] = {1e3, 1.5e3};
  data.dirichlet = [](const Point<3> &p, unsigned int, double, double &v) {
    v = 0;
    return p[0] < 1e-12;
  };

  for (const unsigned int degree : {1u, 2u})
    for (const auto flux : testing::dg_fluxes)
      {
        const dg::Parameters p =
          testing::dg_parameters(dg::Parameters::Element::dgq, degree, flux);
        const auto    fe = p.make_element<3>();
        dg::System<3> system(tria, *fe, 3, p, data);
        std::cout << testing::describe(p) << ":\n  ";
        system.assemble(10, 1);
        testing::check_below("asymmetry", asymmetry(system.matrix), 1e-14);
        const Vector<double> u =
          testing::cellwise_affine(system, cell_rotation);
        const std::vector<Tensor<2, 3>> fitted         = system.rotations(u);
        double                          rotation_error = 0;
        for (const auto &cell : system.dof_handler.active_cell_iterators())
          rotation_error = testing::worst(
            rotation_error,
            (fitted[cell->active_cell_index()] - cell_rotation(cell)).norm());
        std::cout << "  ";
        testing::check_below("fitted rotation error", rotation_error, 1e-12);
        system.assemble(10, 1, &u);
        std::cout << "  corotated ";
        testing::check_below("asymmetry", asymmetry(system.matrix), 1e-14);
        for (const double eta : {1e-3, 0.1, 10.})
          {
            system.assemble(eta, 1);
            std::cout << "  eta = " << eta << ": K " << definiteness(system)
                      << std::endl;
          }
        if (flux == dg::Parameters::Flux::babuska_zlamal)
          {
            try
              {
                system.settle_penalty(1);
                std::cout << "  automatic: NOT rejected" << std::endl;
              }
            catch (const ExceptionBase &)
              {
                std::cout << "  automatic: rejected" << std::endl;
              }
            continue;
          }
        system.settle_penalty(1);
        std::cout << "  automatic: eta = " << system.penalty() << " after "
                  << system.penalty_doublings << " doublings, K "
                  << definiteness(system) << std::endl;
        system.assemble(system.penalty() / 2, 1);
        std::cout << "  half of it: K " << definiteness(system) << std::endl;
      }

  // One square of the Poisson problem, weak Dirichlet data on its four
  // sides: at eta = 1 the interior penalty matrix is singular in exact
  // arithmetic (smallest eigenvalue at round-off level).
  Triangulation<2> square;
  GridGenerator::hyper_cube(square);
  dg::ProblemData<2> poisson;
  poisson.materials = {{1, 0}};
  poisson.dirichlet = [](const Point<2> &, unsigned int, double, double &v) {
    v = 0;
    return true;
  };
  const dg::Parameters p =
    testing::dg_parameters(dg::Parameters::Element::dgq,
                           1,
                           dg::Parameters::Flux::interior_penalty);
  const auto    fe = p.make_element<2>();
  dg::System<2> system(square, *fe, 1, p, poisson);
  for (const double eta : {0.9, 1., 1.1, 2.})
    {
      system.assemble(eta, 1);
      LAPACKFullMatrix<double> dense(system.matrix.m());
      dense = system.matrix;
      const Vector<double> eigenvalues =
        testing::symmetric_eigenvalues(dense, system.matrix.linfty_norm());
      std::cout << "Poisson on one square, IP FE_DGQ(1), eta = " << eta
                << ": K " << dg::to_string(system.check_definiteness())
                << ", smallest eigenvalue / largest ";
      // Singular at eta = 1 in exact arithmetic: the sign of the computed
      // ratio is round-off there.
      const double ratio = eigenvalues(0) / eigenvalues(eigenvalues.size() - 1);
      if (std::abs(ratio) < 1e-12)
        std::cout << "0 to round-off (below 10^-12 in magnitude)";
      else
        std::cout << std::setprecision(2) << ratio << std::setprecision(6);
      std::cout << std::endl;
    }
}
