// Corotated DG warps each cell's terms with its own rotation, and each
// face's with the rotations of its two cells. Where neighbours turn by
// different rotations, the warped face terms are not congruent to the
// linear ones, so a penalty that makes the linear matrix positive definite
// need not, in principle, make the warped one so (a 2D model of two cells
// found negative eigenvalues). The penalty is settled on the linear matrix,
// at least its smallest stable value eta*, so this checks the warped
// matrices just above it: a 2 x 8 x 2 cantilever, mu = 1, lambda = 0 and
// 1.5, DGQ1 and DGQ2 interior penalty, eta* of the linear matrix by
// bisection, then the matrices warped with rotations by 90 degrees about z
// in every other cell (by the parity of i + j + k), by 30 degrees about x
// likewise, and by random rotations up to 90 degrees in every cell, at
// 1.01, 1.05 and 1.5 eta*. All are positive definite.

#include <iomanip>
#include <iostream>
#include <random>

#include "../tests.h"
#include "dg_tests.h"

using namespace dealii;
using namespace ddfem;

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Triangulation<3>                         tria;
  testing::make_beam(tria, 2);
  for (const double lambda : {0., 1.5})
    for (const unsigned int degree : {1u, 2u})
      {
        dg::Parameters p =
          testing::dg_parameters(dg::Parameters::Element::dgq,
                                 degree,
                                 dg::Parameters::Flux::interior_penalty);
        p.formulation               = dg::Parameters::Formulation::corotated;
        const auto               fe = p.make_element<3>();
        const dg::ProblemData<3> data =
          testing::cantilever_data(tria, {1, lambda});
        dg::System<3> system(tria, *fe, 3, p, data);
        const auto    definite = [&](const double eta) {
          system.assemble(eta, 1);
          return system.check_definiteness() ==
                 dg::Definiteness::positive_definite;
        };
        double low = 1e-3, high = 1e3;
        AssertThrow(!definite(low) && definite(high), ExcMessage("no bracket"));
        while (high / low > 1 + 1e-4)
          (definite(std::sqrt(low * high)) ? high : low) =
            std::sqrt(low * high);
        std::cout << "lambda = " << lambda << ", DGQ" << degree
                  << ": eta* = " << std::setprecision(3) << high << std::endl;
        // Rotations by 90 degrees about z in every other cell, by 30
        // degrees about x, and random ones (up to 90 degrees about random
        // axes) in every cell.
        std::mt19937                           random(1);
        std::uniform_real_distribution<double> uniform(-1, 1);
        std::vector<Tensor<2, 3>>              random_rotations;
        for (unsigned int c = 0; c < tria.n_active_cells(); ++c)
          {
            Tensor<1, 3> axis(
              {uniform(random), uniform(random), uniform(random)});
            random_rotations.push_back(
              testing::rotation_about(axis / axis.norm(),
                                      90 * uniform(random)));
          }
        for (const unsigned int field : {0u, 1u, 2u})
          {
            const Vector<double> u =
              testing::cellwise_affine(system, [&](const auto &cell) {
                const Point<3> c = cell->center();
                const bool     parity =
                  int(std::floor(2 * c[0]) + std::floor(2 * c[1]) +
                      std::floor(2 * c[2])) %
                  2;
                if (field == 2)
                  return random_rotations[cell->active_cell_index()];
                return !parity ?
                         unit_symmetric_tensor<3>() :
                       field == 0 ?
                         testing::rotation_about(Tensor<1, 3>({0, 0, 1}), 90) :
                         testing::rotation_about(Tensor<1, 3>({1, 0, 0}), 30);
              });
            for (const double factor : {1.01, 1.05, 1.5})
              {
                system.assemble(factor * high, 1, &u);
                std::cout << "  field " << field << " warped at " << factor
                          << " eta*: "
                          << dg::to_string(system.check_definiteness())
                          << std::endl;
              }
          }
      }
}
