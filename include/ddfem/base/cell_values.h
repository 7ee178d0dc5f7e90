#ifndef ddfem_base_cell_values_h
#define ddfem_base_cell_values_h

#include <deal.II/base/tensor.h>
#include <deal.II/fe/fe_values.h>

#include <type_traits>

namespace ddfem
{
  /**
   * FEValues for a cell, and the translation from its quadrature points to
   * the cell's.
   */
  template <int dim>
  struct TranslatedValues
  {
    /// Shape values and gradients and JxW values that hold on the cell.
    const dealii::FEValues<dim> &values;
    /// Added to values.quadrature_point(q), gives the cell's point q.
    dealii::Tensor<1, dim> shift;
  };

  /**
   * FEValues for @p cell that do not depend on the cells the object saw
   * before, and so not on the number of threads.
   *
   * deal.II 9.4's FEValues, running on one thread, keeps the Jacobians and
   * shape gradients of the previous cell for a translate of it
   * (CellSimilarity::translation); with more threads it recomputes them for
   * every cell. The two differ in round-off, so an assembly would give
   * other results with one thread than with two.
   *
   * This function reinitializes the object on @p reference, and then on
   * @p cell only if @p cell is not a translate of @p reference. So the
   * values are:
   * - for a translate: those of @p reference, the same whether reused from
   *   an earlier translate or recomputed;
   * - otherwise: the cell's own, computed fresh, since @p cell is not a
   *   translate of @p reference, the previous cell.
   *
   * Everything that depends on position (quadrature points, and the cell
   * and DoF indices a MeshWorker::ScratchData keeps) then belongs to
   * @p reference: add the returned shift to quadrature points. This holds
   * for mappings that the vertices determine (MappingQ1), on which a
   * vertex translate is a translate. Nothing else may reinitialize the
   * object between calls. @p reinit(c) reinitializes the FEValues object
   * on the cell c and returns it.
   */
  template <int dim,
            typename Reinit,
            typename Iterator,
            typename = std::enable_if_t<
              std::is_invocable_v<const Reinit &, const Iterator &>>>
  TranslatedValues<dim>
  reinit_thread_independently(const Reinit   &reinit,
                              const Iterator &cell,
                              const Iterator &reference)
  {
    const dealii::FEValues<dim> &values = reinit(reference);
    if (cell->is_translation_of(reference))
      return {values, cell->vertex(0) - reference->vertex(0)};
    return {reinit(cell), dealii::Tensor<1, dim>()};
  }

  /// reinit_thread_independently() of @p fe_values itself.
  template <int dim, typename Iterator>
  TranslatedValues<dim>
  reinit_thread_independently(dealii::FEValues<dim> &fe_values,
                              const Iterator        &cell,
                              const Iterator        &reference)
  {
    return reinit_thread_independently<dim>(
      [&fe_values](const Iterator &c) -> const dealii::FEValues<dim> & {
        fe_values.reinit(c);
        return fe_values;
      },
      cell,
      reference);
  }
} // namespace ddfem

#endif
