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
   * The offline half of data-driven FEM: sampling 2x2x2 blocks, fitting
   * metamaterials, cube symmetries, compression, the second level and the
   * HDF5 database.
   */
  namespace coarsening
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
