// The condition number of the stiffness matrix grows like h^-2 for every
// method of the DG convergence study, and DG's is above CG's of the same
// degree on the same mesh (doc/dg.md, paper figure 4). Exact
// condition numbers, not the study's Lanczos estimates: the extreme
// eigenvalues (LAPACK dsyevx) of the dense matrix restricted to the
// unconstrained DoFs, for the study's 2D Poisson problem (Dirichlet weak for
// DG, strong for CG) on 4^2, 8^2 and 16^2 cells, FE_DGQ and FE_DGP,
// eta = 10. CG Q1's condition numbers are checked against their closed
// form.

#include <deal.II/fe/fe_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <ddfem/base/exceptions.h>
#include <ddfem/dg/studies.h>
#include <ddfem/dg/system.h>

#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "../tests.h"
#include "dg_tests.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  /// The exact condition number of the matrix of @p method on the n x n
  /// mesh of the unit square, DG methods with @p element.
  double
  condition_number(const dg::StudyMethod        &method,
                   const dg::Parameters::Element element,
                   const unsigned int            n)
  {
    Triangulation<2> tria;
    GridGenerator::subdivided_hyper_cube(tria, n, 0, 1);
    dg::ProblemData<2> data;
    data.materials.assign(tria.n_active_cells(), {1, 0});
    data.dirichlet = [](const Point<2> &, unsigned int, double, double &v) {
      v = 0;
      return true;
    };
    const dg::Parameters p =
      testing::dg_parameters(element, method.degree, method.flux);
    const std::unique_ptr<FiniteElement<2>> fe =
      method.continuous ? std::make_unique<FE_Q<2>>(method.degree) :
                          p.make_element<2>();
    dg::System<2> system(tria, *fe, 1, p, data);
    system.assemble(10, 1);

    // A constrained row holds only an artificial diagonal entry.
    std::vector<unsigned int> free;
    for (unsigned int i = 0; i < system.dof_handler.n_dofs(); ++i)
      if (!system.constraints.is_constrained(i))
        free.push_back(i);
    LAPACKFullMatrix<double> K(free.size());
    for (unsigned int i = 0; i < free.size(); ++i)
      for (unsigned int j = 0; j < free.size(); ++j)
        K(i, j) = system.matrix.el(free[i], free[j]);
    // The free rows' norm is at most the whole matrix's.
    const Vector<double> eigenvalues =
      testing::symmetric_eigenvalues(K, system.matrix.linfty_norm());
    AssertThrow(eigenvalues(0) > 0, ExcMessage(method.name + ": indefinite"));
    return eigenvalues(eigenvalues.size() - 1) / eigenvalues(0);
  }
} // namespace

/// Prints the condition numbers of @p method on the grids and the
/// exponent of their growth on the finest pair; returns the finest one.
double
print_growth(const dg::StudyMethod        &method,
             const dg::Parameters::Element element,
             const std::string            &label)
{
  std::vector<double> kappa;
  std::cout << label << ": condition number" << std::scientific
            << std::setprecision(3);
  for (const unsigned int n : {4u, 8u, 16u})
    {
      kappa.push_back(condition_number(method, element, n));
      std::cout << ' ' << kappa.back();
    }
  // The exponents p of kappa ~ h^-p on the two pairs of grids: 2 within
  // 0.1 on the finest pair, or still on the way there, with the distance to
  // 2 at most half of that on the coarser pair.
  const double coarse = std::log2(kappa[1] / kappa[0]);
  const double fine   = std::log2(kappa[2] / kappa[1]);
  const bool   tends  = std::abs(fine - 2) <= 0.1 ||
                     std::abs(fine - 2) <= 0.5 * std::abs(coarse - 2);
  std::cout << std::fixed << std::setprecision(2) << "; h^-" << coarse
            << ", then h^-" << fine << ": "
            << (tends ? "tends to h^-2" : "does NOT tend to h^-2") << std::endl;
  return kappa.back();
}

/**
 * The condition number of CG Q1's matrix on the n x n mesh, in closed form:
 * with strong Dirichlet conditions it is K1 x M1 + M1 x K1 on the interior
 * nodes, whose 1D stiffness and mass matrices have the eigenvalues
 * k_j = (2 - 2 cos t_j) / h and m_j = h (4 + 2 cos t_j) / 6, t_j = j pi / n,
 * j = 1..n-1, and the eigenvalues of the sum are k_j m_l + m_j k_l.
 */
double
q1_condition_number(const unsigned int n)
{
  const double h = 1. / n;
  const auto   k = [&](const unsigned int j) {
    return (2 - 2 * std::cos(j * numbers::PI / n)) / h;
  };
  const auto m = [&](const unsigned int j) {
    return h * (4 + 2 * std::cos(j * numbers::PI / n)) / 6;
  };
  double low = std::numeric_limits<double>::max(), high = 0;
  for (unsigned int j = 1; j < n; ++j)
    for (unsigned int l = 1; l < n; ++l)
      {
        const double lambda = k(j) * m(l) + m(j) * k(l);
        low                 = std::min(low, lambda);
        high                = std::max(high, lambda);
      }
  return high / low;
}

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  // Method names outside the study's six are errors (two words used to be
  // enough: "XY lin" was IP lin, "CG quad" CG Q2).
  for (const std::string name : {"XY lin", "CG quad", "IP Q1"})
    try
      {
        dg::parse_methods(name);
        std::cout << name << ": NO ERROR" << std::endl;
      }
    catch (const ExceptionBase &e)
      {
        std::cout << name << ": " << message_of(e) << std::endl;
      }
  // The condition numbers on 16^2 of CG, by degree.
  std::map<unsigned int, double> cg;
  {
    const dg::StudyMethod q1         = dg::parse_methods("CG Q1")[0];
    double                difference = 0;
    for (const unsigned int n : {4u, 8u, 16u})
      difference =
        testing::worst(difference,
                       std::abs(
                         condition_number(q1, dg::Parameters::Element::dgq, n) /
                           q1_condition_number(n) -
                         1));
    testing::check_below("CG Q1 on 4^2, 8^2, 16^2: relative difference of "
                         "the condition numbers from the closed form",
                         difference,
                         1e-10);
  }
  for (const dg::StudyMethod &method : dg::parse_methods("CG Q1, CG Q2"))
    cg[method.degree] =
      print_growth(method, dg::Parameters::Element::dgq, method.name);
  for (const auto element : testing::dg_elements)
    {
      std::ostringstream ratios;
      for (const dg::StudyMethod &method :
           dg::parse_methods("BZ lin, BZ quad, IP lin, IP quad"))
        {
          const dg::Parameters p =
            testing::dg_parameters(element, method.degree, method.flux);
          const double ratio =
            print_growth(method,
                         element,
                         method.name + " " + p.element_name()) /
            cg[method.degree];
          ratios << ' ' << method.name << ' ' << std::fixed
                 << std::setprecision(0) << ratio
                 << (ratio > 1 ? "" : " (NOT above CG)");
        }
      std::cout << "On 16^2, over CG of the same degree:" << ratios.str()
                << std::endl;
    }
}
