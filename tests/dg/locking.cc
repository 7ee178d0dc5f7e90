// Near incompressibility: the tip deflection of a cantilever (2 x 8 x 2
// cells, E = 1000, nu = 0.3, 0.49, 0.499) with CG and DG, divided by that
// of CG Q2 on the twice refined mesh (the reference, nearly free of
// locking). A locking method's ratio drops as nu -> 0.5; a locking-free
// one keeps it: the last lines say, for each method, whether its ratio at
// nu = 0.499 is at least 0.97 of that at nu = 0.3 (doc/dg.md: IP FE_DGQ(2)
// and FE_DGP(2) are, CG Q1 and Q2 and the linear DG elements are not).
// The DG penalty is automatic and must end positive definite.

#include <deal.II/fe/fe_q.h>

#include <iostream>

#include "../tests.h"
#include "dg_tests.h"

using namespace dealii;
using namespace ddfem;

namespace
{
  /// Tip deflection on the n x 4n x n mesh.
  double
  tip(const unsigned int      n,
      const double            nu,
      const FiniteElement<3> &fe,
      const dg::Parameters   &p,
      std::string            &note)
  {
    Triangulation<3> tria;
    testing::make_beam(tria, n);
    const double             E    = 1000;
    const dg::ProblemData<3> data = testing::cantilever_data(
      tria, {E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))});
    dg::System<3>          system(tria, fe, 3, p, data);
    const dg::Definiteness d = system.settle_penalty(1);
    std::ostringstream     text;
    if (!system.continuous())
      text << "eta " << system.penalty() << ", " << dg::to_string(d);
    note = text.str();
    system.solve();
    return testing::tip_deflection(system);
  }
} // namespace

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  dg::Parameters                           cg;
  cg.dirichlet = dg::Parameters::Dirichlet::strong;
  dg::Parameters ip, bz;
  bz.flux    = dg::Parameters::Flux::babuska_zlamal;
  bz.penalty = 10;
  std::cout << std::setprecision(4);
  // Each method's ratios, in the order of the table.
  std::vector<std::pair<std::string, std::vector<double>>> ratios;
  for (const double nu : {0.3, 0.49, 0.499})
    {
      std::string  note;
      const double reference = tip(4, nu, FE_Q<3>(2), cg, note);
      std::cout << "nu = " << nu << ": reference deflection " << reference
                << std::endl;
      const auto report = [&](const std::string      &name,
                              const FiniteElement<3> &fe,
                              const dg::Parameters   &p) {
        const double ratio = tip(2, nu, fe, p, note) / reference;
        std::cout << "  " << std::left << std::setw(14) << name << std::right
                  << " ratio " << std::setw(6) << ratio << "  " << note
                  << std::endl;
        auto method =
          std::find_if(ratios.begin(), ratios.end(), [&](const auto &m) {
            return m.first == name;
          });
        if (method == ratios.end())
          method = ratios.insert(ratios.end(), {name, {}});
        method->second.push_back(ratio);
      };
      report("CG Q1", FE_Q<3>(1), cg);
      report("CG Q2", FE_Q<3>(2), cg);
      for (const unsigned int k : {1u, 2u})
        for (const auto element : testing::dg_elements)
          {
            ip.degree  = k;
            ip.element = element;
            report(testing::describe(ip), *ip.make_element<3>(), ip);
          }
      bz.degree = 1;
      report(testing::describe(bz) + " 10", *bz.make_element<3>(), bz);
    }
  std::cout << "Ratio at nu = 0.499 at least 0.97 of that at nu = 0.3:"
            << std::endl;
  for (const auto &[name, r] : ratios)
    std::cout << "  " << std::left << std::setw(14) << name << std::right << " "
              << (r.back() >= 0.97 * r.front() ? "yes, locking-free" : "no")
              << std::endl;
}
