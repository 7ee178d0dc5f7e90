// With a large penalty the DG solution approaches the CG one on the same
// mesh (the paper's figure 1 argument): the tip deflection of a cantilever
// with IP and BZ, FE_DGQ(1), for growing eta, against continuous FE_Q(1).
// Its relative difference must fall monotonically, by a factor of 8 to 12
// per decade of eta (O(1/eta)), below 1e-5 at the end.

#include <deal.II/fe/fe_q.h>

#include <iostream>

#include "../tests.h"
#include "dg_tests.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  /// The tip deflection of the cantilever solved with @p p and @p fe.
  double
  tip_deflection(const Triangulation<3>   &tria,
                 const FiniteElement<3>   &fe,
                 const dg::Parameters     &p,
                 const dg::ProblemData<3> &data)
  {
    dg::System<3> system(tria, fe, 3, p, data);
    system.settle_penalty(1);
    system.solve();
    return testing::tip_deflection(system);
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Triangulation<3>                         tria;
  testing::make_beam(tria, 2);
  const dg::ProblemData<3> data = testing::cantilever_data(tria, {1e3, 1.5e3});

  dg::Parameters cg;
  cg.dirichlet     = dg::Parameters::Dirichlet::strong;
  const double ref = tip_deflection(tria, FE_Q<3>(1), cg, data);
  std::cout << "CG Q1 tip deflection: " << std::setprecision(5) << ref
            << std::endl;
  for (const auto flux : testing::dg_fluxes)
    {
      dg::Parameters p;
      p.flux = flux;
      std::cout << testing::describe(p) << ":" << std::endl;
      double previous = std::numeric_limits<double>::max();
      bool   monotone = true;
      for (const double eta : {10., 1e2, 1e3, 1e4, 1e5})
        {
          p.penalty = eta;
          const double d =
            std::abs(tip_deflection(tria, *p.make_element<3>(), p, data) -
                     ref) /
            std::abs(ref);
          // The difference is O(1/eta): each decade of eta divides it by
          // about 10, and eta times it is printed, O(1) and so held to its
          // digits by the comparison of the output. The last decade of IP
          // is at round-off's level (factors 9.25 and 9.51 on two hosts),
          // so at the largest eta only the factor's range is checked.
          std::cout << "  eta = " << std::setw(6) << eta << ": ";
          if (eta < 1e5)
            std::cout << "eta |DG - CG| / |CG| = " << std::setprecision(3)
                      << eta * d;
          else
            std::cout << "|DG - CG| / |CG| below 10^-5: "
                      << (d < 1e-5 ? "yes" : "NO");
          if (previous < std::numeric_limits<double>::max())
            std::cout << ", 8 to 12 times smaller: "
                      << (previous / d > 8 && previous / d < 12 ? "yes" : "NO");
          std::cout << std::endl;
          monotone = monotone && d < previous;
          previous = d;
        }
      std::cout << "  decreasing: " << (monotone ? "yes" : "NO") << std::endl;
    }
}
