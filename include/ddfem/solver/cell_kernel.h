#ifndef ddfem_solver_cell_kernel_h
#define ddfem_solver_cell_kernel_h

#include <deal.II/base/tensor.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <ddfem/material/kernel.h>

#include <vector>

namespace ddfem::solver
{
  using namespace dealii;

  /**
   * What one cell contributes to the total energy, its gradient (the
   * internal force vector) and its Hessian (the tangent stiffness).
   */
  struct CellContribution
  {
    /// Strain energy of the cell (J).
    double energy = 0;
    /// Internal forces, dE/du, per local degree of freedom (N).
    Vector<double> residual;
    /// Tangent stiffness d^2E/du^2 (N/m).
    FullMatrix<double> tangent;
    /// Smallest det F over the cell's quadrature points (NaN if any is).
    double min_J = 0;
  };

  /**
   * The element kernel shared by every continuous discretization (fine
   * voxels, coarse metamaterial blocks, block samplers): integrates the
   * material kernel over one cell. @p fe_values must be reinitialized on
   * the cell with gradients and JxW; @p local_u are the cell's
   * displacement coefficients; @p materials holds one material record per
   * quadrature point. The FE must be primitive and vector valued with three
   * components.
   *
   * Returns false if det F <= 0 at any quadrature point (the energy is
   * +infinity); @p result.min_J is set in any case.
   */
  bool
  integrate_cell(const FEValues<3>                   &fe_values,
                 const Vector<double>                &local_u,
                 const material::MaterialPoint *const materials,
                 const material::KernelOutput         what,
                 CellContribution                    &result);

  /**
   * The deformation gradient F = I + grad u at every quadrature point of
   * the cell @p fe_values is initialized on.
   */
  void
  deformation_gradients(const FEValues<3>         &fe_values,
                        const Vector<double>      &local_u,
                        std::vector<Tensor<2, 3>> &F);
} // namespace ddfem::solver

#endif
