#ifndef ddfem_material_kernel_h
#define ddfem_material_kernel_h

#include <deal.II/base/tensor.h>

namespace ddfem::material
{
  using namespace dealii;

  /**
   * The material data carried by one quadrature point: a compressible
   * Neo-Hookean solid plus an optional anisotropic spring,
   *
   *   psi(F) = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2
   *          + C (|F v| - 1)^2,
   *
   * with I1 = tr(F^T F), J = det F and the unit direction v. Fine cells have
   * C = 0; coarse metamaterial points carry fitted values. Units: mu,
   * lambda and C in Pa (energy per reference volume).
   */
  struct MaterialPoint
  {
    /// Shear modulus (Pa).
    double mu = 0;
    /// Lame's first parameter (Pa).
    double lambda = 0;
    /// Stiffness C of the anisotropic spring (Pa); 0 disables it.
    double anisotropy = 0;
    /// Unit direction v of the anisotropic spring (reference frame).
    Tensor<1, 3> direction;
  };

  /**
   * What the kernel is asked to compute: each level includes the ones
   * before it.
   */
  enum class KernelOutput
  {
    /// Energy density only.
    energy,
    /// Energy density and first Piola-Kirchhoff stress.
    stress,
    /// Energy, stress and the tangent dP/dF.
    tangent
  };

  /**
   * The kernel's result at one quadrature point.
   */
  struct KernelResult
  {
    /// Strain energy density psi (J/m^3).
    double energy = 0;
    /// First Piola-Kirchhoff stress P = dpsi/dF (Pa).
    Tensor<2, 3> stress;
    /// Tangent A_{iJkL} = dP_{iJ}/dF_{kL} (Pa).
    Tensor<4, 3> tangent;
  };

  /**
   * The one constitutive kernel of ddfem: evaluates energy density, first
   * Piola-Kirchhoff stress and its tangent of the material @p m at the
   * deformation gradient @p F. The fine solver, the coarse solver and the
   * block sampler all call this function.
   *
   * Returns false, leaving @p result unspecified, if det F <= 0 (the energy
   * is +infinity there); callers treat that as an inadmissible state.
   */
  bool
  evaluate(const Tensor<2, 3>  &F,
           const MaterialPoint &m,
           const KernelOutput   what,
           KernelResult        &result);

  /**
   * The largest principal stretch deviation max_i |lambda_i - 1| of @p F,
   * where lambda_i are the principal stretches (square roots of the
   * eigenvalues of F^T F): the strain measure that the database's sampling
   * range and the runs' strain statistics share.
   */
  double
  principal_strain(const Tensor<2, 3> &F);

  /**
   * The largest principal linearized strain max_i |e_i| of @p F, where e_i
   * are the eigenvalues of sym(F - I): the measure by which the database's
   * sampling scales its magnitudes.
   */
  double
  linearized_strain(const Tensor<2, 3> &F);

  /**
   * Cauchy stress sigma = P F^T / J from a first Piola-Kirchhoff stress.
   * Requires det F > 0.
   */
  Tensor<2, 3>
  cauchy_stress(const Tensor<2, 3> &P, const Tensor<2, 3> &F);

  /**
   * Von Mises equivalent of a Cauchy stress, sqrt(3/2 s:s) with s the
   * deviator.
   */
  double
  von_mises(const Tensor<2, 3> &sigma);

  /**
   * Linear elastic (Hookean) stress sigma = 2 mu eps + lambda tr(eps) I of
   * the small strain eps = sym(@p grad_u), with the Lame parameters @p mu
   * and @p lambda (Pa). It is the linearization of evaluate() at F = I for
   * an isotropic point without anisotropy; the DG discretization uses it.
   */
  template <int dim>
  inline Tensor<2, dim>
  linear_elastic_stress(const Tensor<2, dim> &grad_u,
                        const double          mu,
                        const double          lambda)
  {
    Tensor<2, dim> sigma;
    const double   trace = dealii::trace(grad_u);
    for (unsigned int i = 0; i < dim; ++i)
      {
        for (unsigned int j = 0; j < dim; ++j)
          sigma[i][j] = mu * (grad_u[i][j] + grad_u[j][i]);
        sigma[i][i] += lambda * trace;
      }
    return sigma;
  }
} // namespace ddfem::material

#endif
