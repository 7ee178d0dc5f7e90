#ifndef ddfem_solver_supports_h
#define ddfem_solver_supports_h

#include <deal.II/base/point.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/full_matrix.h>

#include <ddfem/scene/scene.h>

#include <array>
#include <initializer_list>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace ddfem::solver
{
  using namespace dealii;

  /// A prescribed displacement component at a point: (point, component).
  using ConstrainedRow = std::pair<Point<3>, unsigned int>;

  /**
   * Union-find with path halving over the indices 0..n-1 (active cells):
   * the connected parts of a mesh.
   */
  class Components
  {
  public:
    /// n singletons.
    explicit Components(const std::size_t n);

    /// The representative of the part that holds @p i.
    std::size_t
    find(std::size_t i);

    /// Merges the parts that hold @p a and @p b.
    void
    join(const std::size_t a, const std::size_t b);

  private:
    std::vector<std::size_t> parent;
  };

  /// The parts of @p tria's active cells that share vertices (nodes).
  Components
  vertex_connected_parts(const Triangulation<3> &tria);

  /// The parts of @p tria's active cells that share faces (across a
  /// hanging face, the refined side's cells join the coarse cell).
  Components
  face_connected_parts(const Triangulation<3> &tria);

  /**
   * The number of the six rigid body modes that prescribing the (point,
   * component) pairs of @p rows fixes: the rank of the Gram matrix of the
   * modes restricted to those rows (points centered and scaled, the matrix
   * scaled to a unit diagonal, so that the count of rows holding one mode
   * does not hide another).
   */
  unsigned int
  fixed_rigid_modes(const std::vector<ConstrainedRow> &rows);

  /**
   * Component @p component of the six rigid body modes at the position
   * @p r relative to their centre: the translations e_0, e_1, e_2, then the
   * rotations e_k x r about the three axes.
   */
  std::array<double, 6>
  rigid_body_modes(const Tensor<1, 3> &r, const unsigned int component);

  /**
   * Linear conditions on the rigid motions of @p n_parts parts, 6 numbers
   * each (rigid_body_modes() about a centre, lengths in units of a scale):
   * a point two parts share moves alike in both, a held point does not
   * move. The motions the conditions leave free are the null space of
   * their matrix C, one row per condition. With the centre and scale of the
   * parts' extent its entries are geometric and O(1). The block sampler
   * takes a block's zero-energy modes from free_motions(), and
   * require_supported_mesh() counts a group's mechanisms with
   * n_free_motions(). The conditions are stored sparsely (at most 12
   * entries per row), so that many parts cost little until
   * free_motions() is asked for.
   */
  class RigidPartConditions
  {
  public:
    /// No conditions yet on @p n_parts parts; rotations about @p center,
    /// lengths in units of @p scale.
    RigidPartConditions(const unsigned int n_parts,
                        const Point<3>    &center,
                        const double       scale);

    /// Component @p component at @p x moves alike in parts @p a and @p b.
    void
    join(const Point<3>    &x,
         const unsigned int component,
         const unsigned int a,
         const unsigned int b);

    /// Component @p component at @p x of part @p a does not move.
    void
    hold(const Point<3> &x, const unsigned int component, const unsigned int a);

    /**
     * An orthonormal basis of the free motions (one column each, 6
     * numbers per part): the eigenvectors of the dense Gram matrix C^T C
     * whose eigenvalues are below 1e-8. Its cost grows with the cube of
     * the number of parts: for a few parts, such as a block's children.
     */
    FullMatrix<double>
    free_motions() const;

    /**
     * The number of free motions: 6 n_parts minus the rank of C, which
     * SuiteSparseQR's rank-revealing sparse QR factorization estimates
     * (a column whose norm falls to its default tolerance, 20 (m + n)
     * eps times the largest column norm, counts as dependent). The
     * motions of hinged voxels are free exactly, up to round-off, so
     * this counts those of thousands of parts at the cost of a sparse
     * factorization. Throws std::bad_alloc if SuiteSparseQR runs out of
     * memory, ExcMessage if it fails otherwise.
     */
    unsigned int
    n_free_motions() const;

  private:
    /// Adds the condition sum_p sign_p (motion of part p at @p x, component
    /// @p component) = 0 over the (part, sign) pairs @p parts.
    void
    add_condition(
      const Point<3>                                              &x,
      const unsigned int                                           component,
      const std::initializer_list<std::pair<unsigned int, double>> parts);

    unsigned int n_parts;
    Point<3>     center;
    double       scale;
    /// The rows of C: (column, value) pairs, columns 6 p + mode.
    std::vector<std::vector<std::pair<unsigned int, double>>> conditions;
  };

  /// The vector component of every DoF of @p dof_handler (an FESystem).
  std::vector<unsigned int>
  dof_components(const DoFHandler<3> &dof_handler);

  /**
   * Throws ExcMessage unless there are Dirichlet rows, and the rows of
   * every part of @p parts (the
   * active cells of @p tria, joined by what the discretization couples)
   * fix all six rigid body motions of that part. @p rows holds each part's
   * rows under its representative. @p shared names what joins cells into a
   * part ("node" for continuous elements, "face" for DG), for the message
   * about a part that floats free of the others.
   */
  void
  require_supported_parts(
    const Triangulation<3>                                   &tria,
    Components                                               &parts,
    const std::map<std::size_t, std::vector<ConstrainedRow>> &rows,
    const std::string                                        &shared);

  /// The boundary face @p f of the voxel mesh's @p cell, as
  /// BoundaryConditions::check_regions() and check_effects() take it.
  scene::BoundaryFace
  voxel_face(const Triangulation<3>::active_cell_iterator &cell,
             const unsigned int                            f);

  /**
   * Throws ExcMessage unless the Dirichlet rows of @p tria's cells fix
   * all six rigid body motions of every part whose cells share vertices
   * (require_supported_parts()), and no part whose cells share faces hangs
   * on the others along an edge or at a corner only (a mechanism): each
   * such part must be held by its rows and the nodes it shares with the
   * other parts, and the parts that are not held by their rows and by
   * parts held already (in turn) must be held as a group
   * (RigidPartConditions::n_free_motions(), whatever the group's size).
   * @p cell_rows lists, per active cell, the rows of its constrained nodes
   * (a node shared by cells may appear in each).
   */
  void
  require_supported_mesh(
    const Triangulation<3>                         &tria,
    const std::vector<std::vector<ConstrainedRow>> &cell_rows);

  /**
   * The checks of the fine model on the voxels themselves, for coarse
   * models, whose blocks may bridge a gap between voxels or reach past the
   * solid: every boundary condition of @p scene acts on a vertex or a
   * boundary face of its solid voxels (BoundaryConditions::check_regions())
   * and does something there (BoundaryConditions::check_effects()),
   * and the conditions at the vertices support the voxels as
   * require_supported_mesh() asks. These are the checks of a fine model of
   * degree 1 (at degree 2 the fine model also has nodes between the
   * vertices). Builds only the fine mesh, no degrees of freedom.
   */
  void
  check_voxel_scene(const scene::Scene &scene);
} // namespace ddfem::solver

#endif
