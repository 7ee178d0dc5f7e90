// material::linear_elastic_stress, which the DG discretization uses, must
// be the linearization of the one constitutive kernel at F = I:
// sigma(grad u) = A(I) : grad u for an isotropic point without anisotropy.

#include <ddfem/material/kernel.h>

#include <iostream>

#include "../tests.h"

using namespace dealii;
using namespace ddfem;

int
main()
{
  material::MaterialPoint point;
  point.mu     = 3e5;
  point.lambda = 7e5;
  material::KernelResult at_identity;
  material::evaluate(unit_symmetric_tensor<3>(),
                     point,
                     material::KernelOutput::tangent,
                     at_identity);
  Tensor<2, 3> grad;
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 3; ++j)
      grad[i][j] = 0.01 * (1 + i) - 0.003 * j * j + 0.002 * i * j;
  const Tensor<2, 3> linearized =
    double_contract<2, 0, 3, 1>(at_identity.tangent, grad);
  const Tensor<2, 3> sigma =
    material::linear_elastic_stress(grad, point.mu, point.lambda);
  testing::check_below("|sigma - A(I):grad u| / |sigma|",
                       (sigma - linearized).norm() / sigma.norm(),
                       1e-12);
  std::cout << "stress at identity: " << at_identity.stress.norm() << std::endl;
}
