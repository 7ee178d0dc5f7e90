#include <deal.II/base/symmetric_tensor.h>

#include <ddfem/material/kernel.h>

#include <cmath>

namespace ddfem::material
{
  bool
  evaluate(const Tensor<2, 3>  &F,
           const MaterialPoint &m,
           const KernelOutput   what,
           KernelResult        &result)
  {
    const double J = determinant(F);
    if (!(J > 0))
      return false;

    const double log_J = std::log(J);
    result.energy = 0.5 * m.mu * (scalar_product(F, F) - 3.) - m.mu * log_J +
                    0.5 * m.lambda * log_J * log_J;

    // The anisotropic spring C (l - 1)^2 with a = F v, l = |a|.
    Tensor<1, 3> a;
    double       l = 1;
    if (m.anisotropy != 0)
      {
        // Databases are checked for unit directions when they are loaded.
        Assert(std::abs(m.direction.norm() - 1) < 1e-6,
               ExcMessage("The spring direction must be a unit vector."));
        a = F * m.direction;
        l = a.norm();
        result.energy += m.anisotropy * (l - 1.) * (l - 1.);
      }

    if (what == KernelOutput::energy)
      return true;

    // P = mu F + (lambda ln J - mu) F^{-T} + 2 C (1 - 1/l) (F v) x v
    const Tensor<2, 3> F_inv   = invert(F);
    const double       c_inv_t = m.lambda * log_J - m.mu;
    result.stress              = m.mu * F + c_inv_t * transpose(F_inv);
    const double spring =
      (m.anisotropy != 0) ? 2. * m.anisotropy * (1. - 1. / l) : 0.;
    if (m.anisotropy != 0)
      result.stress += spring * outer_product(a, m.direction);

    if (what == KernelOutput::stress)
      return true;

    // dP_iJ/dF_kL = mu d_ik d_JL + lambda Finv_Ji Finv_Lk
    //             - (lambda ln J - mu) Finv_Jk Finv_Li
    //             + 2C [a_i a_k / l^3 + (1 - 1/l) d_ik] v_J v_L
    const Tensor<1, 3> &v = m.direction;
    const double        aniso_a =
      (m.anisotropy != 0) ? 2. * m.anisotropy / (l * l * l) : 0.;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int J_ = 0; J_ < 3; ++J_)
        for (unsigned int k = 0; k < 3; ++k)
          for (unsigned int L = 0; L < 3; ++L)
            {
              double value = m.lambda * F_inv[J_][i] * F_inv[L][k] -
                             c_inv_t * F_inv[J_][k] * F_inv[L][i];
              if (i == k && J_ == L)
                value += m.mu;
              if (m.anisotropy != 0)
                value += (aniso_a * a[i] * a[k] + (i == k ? spring : 0.)) *
                         v[J_] * v[L];
              result.tangent[i][J_][k][L] = value;
            }
    return true;
  }



  double
  principal_strain(const Tensor<2, 3> &F)
  {
    double strain = 0;
    for (const double c : eigenvalues(symmetrize(transpose(F) * F)))
      strain = std::max(strain, std::abs(std::sqrt(std::max(c, 0.)) - 1.));
    return strain;
  }



  double
  linearized_strain(const Tensor<2, 3> &F)
  {
    double strain = 0;
    for (const double e :
         eigenvalues(symmetrize(F - unit_symmetric_tensor<3>())))
      strain = std::max(strain, std::abs(e));
    return strain;
  }



  Tensor<2, 3>
  cauchy_stress(const Tensor<2, 3> &P, const Tensor<2, 3> &F)
  {
    return P * transpose(F) / determinant(F);
  }



  double
  von_mises(const Tensor<2, 3> &sigma)
  {
    const SymmetricTensor<2, 3> s = deviator(symmetrize(sigma));
    return std::sqrt(1.5 * scalar_product(s, s));
  }
} // namespace ddfem::material
