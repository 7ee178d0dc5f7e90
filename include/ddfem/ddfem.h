#ifndef ddfem_ddfem_h
#define ddfem_ddfem_h

/**
 * ddfem: fast simulation of multi-material voxel objects under large
 * deformation (fine continuous, coarse data-driven and discontinuous
 * Galerkin formulations on the same scenes).
 */
namespace ddfem
{
  /**
   * The simulated object: voxel grid, palette, material layouts, boundary
   * conditions, loads, probes, and meshes built from voxels.
   */
  namespace scene
  {}

  /**
   * The constitutive kernel: per-quadrature-point material records and
   * their energy, stress and tangent.
   */
  namespace material
  {}

  /**
   * Discretizations, the cell kernel, Newton's method and linear solvers.
   */
  namespace solver
  {}

  /**
   * Discontinuous Galerkin linear and corotated elasticity: interior
   * penalty and Babuska-Zlamal fluxes, penalty choice, the convergence and
   * cost studies.
   */
  namespace dg
  {}

  /// Output of results: VTU files.
  namespace report
  {}

  /// The command line program: parameters, runs, summary.json.
  namespace app
  {}
} // namespace ddfem

#endif
