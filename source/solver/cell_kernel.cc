#include <ddfem/base/statistics.h>
#include <ddfem/solver/cell_kernel.h>

#include <limits>

namespace ddfem::solver
{
  void
  deformation_gradients(const FEValues<3>         &fe_values,
                        const Vector<double>      &local_u,
                        std::vector<Tensor<2, 3>> &F)
  {
    const FiniteElement<3> &fe = fe_values.get_fe();
    F.assign(fe_values.n_quadrature_points, unit_symmetric_tensor<3>());
    for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
      {
        if (local_u(i) == 0)
          continue;
        const unsigned int c = fe.system_to_component_index(i).first;
        for (unsigned int q = 0; q < F.size(); ++q)
          F[q][c] += local_u(i) * fe_values.shape_grad(i, q);
      }
  }



  bool
  integrate_cell(const FEValues<3>                   &fe_values,
                 const Vector<double>                &local_u,
                 const material::MaterialPoint *const materials,
                 const material::KernelOutput         what,
                 CellContribution                    &result)
  {
    const FiniteElement<3> &fe = fe_values.get_fe();
    const unsigned int      n  = fe.n_dofs_per_cell();
    const bool with_stress     = (what != material::KernelOutput::energy);
    const bool with_tangent    = (what == material::KernelOutput::tangent);

    std::vector<Tensor<2, 3>> F;
    deformation_gradients(fe_values, local_u, F);

    result.energy = 0;
    result.min_J  = std::numeric_limits<double>::max();
    if (with_stress)
      result.residual.reinit(n);
    if (with_tangent)
      result.tangent.reinit(n, n);

    bool                      admissible = true;
    material::KernelResult    k;
    std::vector<Tensor<2, 3>> t(
      n); // t_i[c][L] = sum_J grad_i[J] A[comp_i][J][c][L]
    for (unsigned int q = 0; q < F.size(); ++q)
      {
        result.min_J = min_or_nan(result.min_J, determinant(F[q]));
        if (!admissible || !material::evaluate(F[q], materials[q], what, k))
          {
            admissible = false;
            continue;
          }
        const double JxW = fe_values.JxW(q);
        result.energy += k.energy * JxW;
        if (!with_stress)
          continue;

        for (unsigned int i = 0; i < n; ++i)
          {
            const unsigned int  ci     = fe.system_to_component_index(i).first;
            const Tensor<1, 3> &grad_i = fe_values.shape_grad(i, q);
            result.residual(i) += (k.stress[ci] * grad_i) * JxW;
            if (with_tangent)
              for (unsigned int c = 0; c < 3; ++c)
                for (unsigned int L = 0; L < 3; ++L)
                  t[i][c][L] = grad_i[0] * k.tangent[ci][0][c][L] +
                               grad_i[1] * k.tangent[ci][1][c][L] +
                               grad_i[2] * k.tangent[ci][2][c][L];
          }
        if (with_tangent)
          for (unsigned int i = 0; i < n; ++i)
            for (unsigned int j = i; j < n; ++j)
              {
                const unsigned int cj = fe.system_to_component_index(j).first;
                result.tangent(i, j) +=
                  (t[i][cj] * fe_values.shape_grad(j, q)) * JxW;
              }
      }

    if (with_tangent)
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int j = 0; j < i; ++j)
          result.tangent(i, j) = result.tangent(j, i);
    return admissible;
  }
} // namespace ddfem::solver
