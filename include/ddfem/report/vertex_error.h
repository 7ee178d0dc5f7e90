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
   * on @p coarse (FE_Q(1), any coarsening level, possibly 0) is
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
   * The trilinear field on @p coarse closest to the fine displacement
   * @p u_fine at the vertices of the fine mesh, in the least-squares sense
   * (the sum over fine vertices of the squared distance). Its vertex_error()
   * is what the coarse grid itself costs, whatever the coarse model's
   * materials: no coarse solution has a smaller root-mean-square vertex
   * error, and its mean error is the floor a better metamaterial can
   * approach. Both discretizations must have been built from @p grid.
   */
  Vector<double>
  coarse_fit(const scene::VoxelGrid       &grid,
             const solver::Discretization &fine,
             const Vector<double>         &u_fine,
             const solver::Discretization &coarse);
} // namespace ddfem::report

#endif
