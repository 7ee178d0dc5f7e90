#ifndef ddfem_solver_probe_h
#define ddfem_solver_probe_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/vector.h>

namespace ddfem::solver
{
  using namespace dealii;

  /**
   * The displacement of the field @p u (three components on
   * @p dof_handler) at the probe point @p p: the mean of its values on the
   * cells that hold @p p. A DG field jumps between cells, and a probe on a
   * face, an edge or a vertex gets the average of the sides, as the DG
   * paper stitches its nodes (eq. 17), each cell counting once (also at a
   * hanging node); a continuous field has one value. A
   * point outside the mesh is an error that names Geometry/Probe points.
   * Serves the CG and the DG solvers.
   */
  Tensor<1, 3>
  probe_displacement(const Mapping<3>     &mapping,
                     const DoFHandler<3>  &dof_handler,
                     const Vector<double> &u,
                     const Point<3>       &p);
} // namespace ddfem::solver

#endif
