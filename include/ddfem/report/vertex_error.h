#ifndef ddfem_report_vertex_error_h
#define ddfem_report_vertex_error_h

#include <deal.II/base/tensor.h>
#include <deal.II/lac/vector.h>

#include <ddfem/scene/voxel_grid.h>
#include <ddfem/solver/discretization.h>

#include <vector>

namespace ddfem::report
{
  using namespace dealii;

  /**
   * The displacement of every vertex of @p discretization's mesh in the
   * state @p u, indexed by vertex index (vertices no cell uses get zero).
   */
  std::vector<Tensor<1, 3>>
  vertex_displacements(const solver::Discretization &discretization,
                       const Vector<double>         &u);

  /// The error of a coarse solution against the fine one (DDFEM paper).
  struct VertexError
  {
    /// Mean over fine vertices of |u_coarse - u_fine| / length.
    double mean = 0;
    /// Maximum over fine vertices of |u_coarse - u_fine| / length.
    double max = 0;
    /// Number of fine vertices.
    std::size_t n_vertices = 0;
    /// The longest side of the solid's rest bounding box (m).
    double length = 0;
  };

  /**
   * The DDFEM paper's error measure: the coarse displacement @p u_coarse
   * on @p coarse (FE_Q(1) at any coarsening level, or a level-0 model
   * of any degree, read at the fine vertices) is
   * interpolated trilinearly to every vertex of the fine mesh of
   * @p fine, compared with the fine displacement @p u_fine there, and the
   * distance divided by the longest side of the solid's rest-shape
   * bounding box; mean and maximum over the fine vertices. Both
   * discretizations must have been built from @p grid.
   */
  VertexError
  vertex_error(const scene::VoxelGrid       &grid,
               const solver::Discretization &fine,
               const Vector<double>         &u_fine,
               const solver::Discretization &coarse,
               const Vector<double>         &u_coarse);

  /**
   * The largest displacement at the vertices of the solid voxels of
   * @p grid of the trilinear field @p u on @p model (FE_Q(1), any
   * coarsening level, built from @p grid). A coarse element's nodes may lie
   * in void, where its field is not the part's displacement.
   */
  double
  max_solid_displacement(const scene::VoxelGrid       &grid,
                         const solver::Discretization &model,
                         const Vector<double>         &u);

  /// The coarse grid's best fit to a fine displacement (grid_fit()).
  struct GridFit
  {
    /// The coarse nodal values of the fitted trilinear field.
    Vector<double> field;
    /// The field's vertex_error() against the fine displacement.
    VertexError error;
    /**
     * A lower bound of the mean vertex error of every trilinear field on
     * the coarse grid (same units as VertexError::mean), from duality: no
     * coarse model on that grid, whatever its materials, can do better.
     */
    double lower_bound = 0;
    /// Reweighted least-squares solves taken.
    unsigned int iterations = 0;
    /// Whether the error came within the tolerance of the bound.
    bool converged = false;
  };

  /**
   * The trilinear field on @p coarse with the least mean vertex error
   * against the fine displacement @p u_fine (the DDFEM paper's measure,
   * vertex_error()), and a lower bound of that least error: what the
   * coarse grid itself costs, whatever the coarse model's materials.
   *
   * The mean of distances is minimized by iteratively reweighted least
   * squares: each step solves the weighted least-squares problem over the
   * fine vertices with the weights 1 / sqrt(r^2 + delta^2) of the previous
   * step's distances r (the first step has unit weights; delta is 1e-5
   * times the first step's mean distance), which never increases the
   * smoothed mean. The weighted residuals of each step, scaled to length at
   * most 1, are a feasible point of the dual problem and give the lower
   * bound. The steps stop once the bound is within 0.2 % of the field's
   * mean error, once that mean is at round-off (1e-14 of the largest
   * fine displacement), or after 500 steps.
   * Both discretizations must have been built from @p grid, @p coarse
   * with the trilinear element.
   */
  GridFit
  grid_fit(const scene::VoxelGrid       &grid,
           const solver::Discretization &fine,
           const Vector<double>         &u_fine,
           const solver::Discretization &coarse);
} // namespace ddfem::report

#endif
