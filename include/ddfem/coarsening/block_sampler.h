#ifndef ddfem_coarsening_block_sampler_h
#define ddfem_coarsening_block_sampler_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/vector.h>

#include <ddfem/coarsening/metamaterial.h>
#include <ddfem/scene/voxel_grid.h>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace ddfem::coarsening
{
  using namespace dealii;

  /**
   * How a block's energy is sampled (paper section 4.2) and how its
   * anisotropy directions are estimated (section 4.3). Declared in the prm
   * subsection "Sampling".
   */
  struct SamplingSettings
  {
    /// Number of random patterns per block.
    unsigned int n_directions = 500;
    /// The fraction of the patterns of a mixed block (see for_block())
    /// that are embedded (see BlockSampler::sample()) instead of force
    /// patterns.
    double embedded = 1;
    /// Number of magnitudes per pattern.
    unsigned int n_magnitudes = 5;
    /// Linearized strain of the smallest and the largest magnitude: the
    /// largest over the block's points of a force pattern's linear response
    /// or of an embedded pattern's homogeneous strain (before relaxation).
    double min_strain = 0.02;
    /// See min_strain.
    double max_strain = 0.25;
    /// Whether the magnitudes between min_strain and max_strain are spread
    /// with equal ratios (true) or equal steps (false).
    bool geometric_spacing = false;
    /// Relative size of the linear part of the random surface stress.
    double traction_gradient = 0.25;
    /// Number of stretching directions over the sphere (anisotropy).
    unsigned int n_stretch_directions = 500;
    /// Offsets every block's random generator (see DatabaseBuilder).
    unsigned int seed = 0;

    /// Declares the subsection "Sampling".
    static void
    declare_parameters(ParameterHandler &prm);
    /// Reads and validates the subsection "Sampling".
    void
    parse_parameters(ParameterHandler &prm);

    /**
     * The settings for a block whose fine voxels have the material IDs
     * @p voxels (8 of a 2x2x2 block, or 64 of a 4x4x4 one listed child by
     * child): these settings if the block is mixed (its solid voxels hold
     * more than one material) and either has no void voxel or is a 2x2x2
     * block whose solid voxels are joined through faces; otherwise the
     * same with force patterns only. A homogeneous block's embedded
     * samples are exactly the naive element's energy (its periodic
     * fluctuation vanishes), so only force patterns can correct the
     * coarse element there; a homogeneous block with void voxels keeps
     * them too (a lattice's hinges fit better as free blocks). The stiff
     * voxels of a mixed block with void voxels, as in a porous part, carry
     * load through their neighbours, which a free block lacks: its force
     * patterns made them up to a hundred times too soft. Children joined
     * at an edge or a corner alone would relax to no energy, each held at
     * its own corner, and level-2 blocks with void keep force patterns
     * (doc/coarsening.md, "Porous parts").
     */
    SamplingSettings
    for_block(const std::vector<scene::MaterialId> &voxels) const;

    /// Whether pattern @p p of n_directions is an embedded one: a
    /// fraction 'embedded' of them, spread evenly.
    bool
    is_embedded(const unsigned int p) const;

    /// The number of embedded patterns of the n_directions: 0 if
    /// 'embedded' is too small for a whole one.
    unsigned int
    n_embedded() const;
  };

  /**
   * One energy sample of a block: the displacements of the block's corners
   * (what the coarse element sees) and the block's fine strain energy per
   * unit block volume.
   */
  struct Sample
  {
    /// Corner displacements, unit-cube block.
    CornerDisplacements corners;
    /// Fine strain energy (per unit volume of the block).
    double energy = 0;
    /// Largest principal stretch deviation max |lambda_i - 1| over the
    /// quadrature points of the block's solid voxels.
    double strain = 0;
    /// The index of the pattern the sample came from among the patterns of
    /// its kind, force or embedded (for held-out splits).
    unsigned int pattern = 0;
  };

  /**
   * A 2x2x2 block of children on the unit cube, solved with the fine
   * discretization (trilinear hexes, the solvers' cell kernel): the
   * sampler of paper section 4.2. A child is either void (no cell) or
   * carries one material record per point of its rule: the 2-point Gauss
   * rule for fine voxels (8 equal records), the level-1 element's points
   * for level-1 metamaterials (8 fitted records). Both are sampled by the
   * same code.
   *
   * A level-1 child is a block of 2x2x2 voxels, one per point, and may be
   * partly void. The block then follows its voxels, as a block of voxels
   * does: the corners of void voxels are read from the least-squares fit
   * (corners()), force patterns load the faces of solid voxels only
   * (all faces where they admit no self-equilibrated force; the resultant
   * is removed over the nodes they load, boundary_forces()),
   * and the strain measures skip the points of void voxels. Otherwise a node
   * that only void voxels touch, nearly free in its child's fit, is read as a
   * block corner, and the fit learns a block far too soft (doc/coarsening.md,
   * "Level 2 on blocks whose children are partly void").
   *
   * The zero-energy modes of the block at rest are removed by linear
   * constraints (Lagrange multipliers): the six rigid motions and, where
   * children touch only at an edge or a corner (a mechanism), the hinge's
   * relative rotations. The force patterns are made orthogonal to them over
   * the nodes they load (boundary_forces()), so they may pull or push one
   * face-connected group of children against another through the nodes
   * they share, and the hinge carries load in the samples; its free
   * rotation is kept out of them.
   *
   * All sampling functions are const and thread safe.
   */
  class BlockSampler
  {
  public:
    /// The void voxels of children that are blocks of 2x2x2 voxels: bit j
    /// of entry k is set if voxel j (octant j) of child k is void.
    using VoidVoxels = std::array<std::uint8_t, 8>;

    /**
     * Sets up the block. @p children[k] is empty for a void child, or has
     * 8 records, one per point of the child's rule
     * solver::coarse_quadrature(1, @p child_point_offset) (point j in the
     * child's octant j). Fine voxels have the 2-point Gauss rule of the
     * default offset; level-1 metamaterials (their child fits,
     * Database::lookup(c, Fit::child)) have coarsening::child_point_offset,
     * the Gauss rule too. At least one child must be solid.
     *
     * Without @p void_voxels every child is one voxel; with them every
     * child is a block of 2x2x2 voxels (a level-1 metamaterial) whose void
     * voxels they name.
     */
    explicit BlockSampler(
      const std::array<std::vector<material::MaterialPoint>, 8> &children,
      const double child_point_offset              = solver::gauss_point_offset,
      const std::optional<VoidVoxels> &void_voxels = std::nullopt);

    /// Number of nodal degrees of freedom.
    unsigned int
    n_dofs() const
    {
      return dof_handler.n_dofs();
    }

    /// Number of face-connected groups of children (1 if no mechanism).
    unsigned int
    n_groups() const
    {
      return n_components;
    }

    /// Number of zero-energy modes at rest, the constraints: the dimension
    /// of the joint rigid motions of the face-connected groups (6 for one
    /// group; two groups joined at one edge have 7, at one corner 9, but
    /// four children that pairwise share edges, as {0, 3, 5, 6}, have 6).
    unsigned int
    n_zero_energy_modes() const
    {
      return constraints.m();
    }

    /**
     * Energy samples of the block: n_directions random patterns, drawn
     * from a generator seeded with @p seed, each scaled to n_magnitudes
     * magnitudes whose linearized strain is spread over [min_strain,
     * max_strain] in equal steps or, with geometric_spacing, equal ratios
     * (so soft and stiff blocks cover the same strains) and solved with
     * Newton's method. A magnitude whose solve fails ends its pattern: it
     * and the larger ones are dropped and counted in @p n_dropped.
     *
     * Force patterns (paper section 4.2) are the traction of a random,
     * linearly varying stress on the block's surface (boundary_forces())
     * with its resultant force and moment removed, the deformations of a
     * free block.
     *
     * Inside a part, the block's neighbours hold its boundary. A fraction
     * SamplingSettings::embedded of the patterns, spread evenly, are
     * embedded patterns instead: a random homogeneous strain H
     * (symmetric, standard normal entries) that the corners follow
     * exactly and the other nodes follow up to a periodic fluctuation,
     * equal on opposite faces and edges as in a periodic medium, which
     * minimizes the fine energy (relax()). The samples are then the
     * block's homogenized energy. Where a void voxel leaves a node without
     * its periodic partner, the node moves with the rest of its class, or
     * freely if it is alone in it, and a corner without a node follows
     * nothing. A free block deforms mostly through its soft children and
     * a fit to it softens the stiff ones; inside a body the stiff children
     * carry load as well. The database builder passes
     * SamplingSettings::for_block(), so only mixed blocks get embedded
     * patterns.
     */
    std::vector<Sample>
    sample(const SamplingSettings &settings,
           const std::uint64_t     seed,
           unsigned int           &n_dropped) const;

    /**
     * Anisotropy directions (paper section 4.3): stretch the block in
     * n_stretch_directions directions d spread over the sphere and return
     * per point of @p element the block's stiffest direction there. The
     * stretch follows the block's sampling (@p settings, as
     * SamplingSettings::for_block() gives them):
     * - force patterns (SamplingSettings::n_embedded() = 0): the free block
     *   under uniaxial surface stress along d, the same stress for every d
     *   (solved linearly and scaled once, so that the largest strain of any
     *   direction is 0.01). The stretch l = |F d| of the coarse element's F
     *   is measured at every point, and the direction is the principal axis
     *   of sum_d (l - 1)^2 d d^T with the least stretch;
     * - embedded patterns: the uniaxial strain d d^T, which the corners
     *   follow and the other nodes up to the relaxed periodic fluctuation.
     *   The coarse F is then the same at every point and cannot tell the
     *   points apart, so the fine energy W_k(d) of the point's child k is
     *   measured instead, and the direction is the principal axis of
     *   sum_d W_k(d) d d^T with the largest energy. A stiff child in a
     *   column along x carries the energy of a stretch along x and little
     *   of a transverse one, which the soft children take. Should the
     *   relaxation of a small strain fail, the free block's test is used.
     */
    std::vector<Tensor<1, 3>>
    anisotropy_directions(const SamplingSettings &settings,
                          const CoarseElement    &element) const;

    /// The fine strain energy of the block for nodal displacements @p u;
    /// false if inadmissible (det F <= 0).
    bool
    energy(const Vector<double> &u, double &energy) const;

    /**
     * The corner displacements the coarse element sees (the restriction r
     * of paper eq. 3): the nodal value at a corner whose voxel is solid;
     * at a corner whose voxel is void, the least-squares trilinear fit of
     * the field at the corners of the solid voxels (the fine nodes; where
     * the children are voxels, the nodes).
     */
    CornerDisplacements
    corners(const Vector<double> &u) const;

    /// The nodal vector of the homogeneous strain u = H (x - centre) of the
    /// unit block.
    Vector<double>
    homogeneous_strain(const Tensor<2, 3> &H) const;

    /**
     * Minimizes the fine energy over the periodic fluctuation @p w added
     * to the nodal displacements @p u_base (see sample()); @p w is the
     * initial guess on input. Returns false if Newton's method fails.
     */
    bool
    relax(const Vector<double> &u_base, Vector<double> &w) const;

    /// @p u_base plus the periodic fluctuation @p w at every node.
    Vector<double>
    add_fluctuation(const Vector<double> &u_base,
                    const Vector<double> &w) const;

    /// Number of fluctuation unknowns (3 per periodic class of nodes).
    unsigned int
    n_fluctuation_dofs() const
    {
      return n_periodic;
    }

    /**
     * The nodal forces of a force pattern: the traction sigma(x) n on the
     * block's outer boundary, lumped to the vertices of the children's
     * faces that lie on the unit cube's surface (a quarter of the face per
     * vertex, where it is a solid voxel's face; all quarters where those
     * admit no self-equilibrated force: no solid voxel reaches the surface,
     * or all meet it at one node), less its resultant force and moment (and
     * a hinge's, see n_zero_energy_modes()) removed over the nodes it
     * loads. The nodes it does not load, inside the block or touched by
     * void voxels only, stay free of force. Zero where the traction is its
     * resultant force and moment alone, up to round-off (then no pattern,
     * no stretch).
     */
    Vector<double>
    boundary_forces(
      const std::function<Tensor<2, 3>(const Point<3> &)> &stress) const;

    /// The nodal vector of a displacement field given at every node.
    Vector<double>
    interpolate(const std::function<Tensor<1, 3>(const Point<3> &)> &u) const;

  private:
    /**
     * Solves the block under nodal forces @p f; @p u is the initial guess
     * on input. Returns false if Newton's method fails.
     */
    bool
    solve(const Vector<double> &f, Vector<double> &u) const;

    /// The fine strain energy of each child (0 for void children) for
    /// nodal displacements @p u; false if inadmissible (det F <= 0).
    bool
    child_energies(const Vector<double>  &u,
                   std::array<double, 8> &energies) const;

    /// Energy, internal forces and, if @p tangent, stiffness at @p u.
    bool
    assemble(const Vector<double> &u,
             const bool            tangent,
             double               &energy,
             Vector<double>       &residual,
             FullMatrix<double>   &stiffness) const;

    /// The saddle-point matrix [K G^T; G 0], LU-factorized into @p A.
    /// Returns false if it is exactly singular (LAPACK found a zero pivot).
    bool
    factorize(const FullMatrix<double> &K, LAPACKFullMatrix<double> &A) const;

    /// Solves the factorized saddle point for right-hand side @p b.
    Vector<double>
    constrained_solve(const LAPACKFullMatrix<double> &A,
                      const Vector<double>           &b) const;

    /// The stiffest direction per point of the free block under uniaxial
    /// stress (see anisotropy_directions()).
    std::vector<Tensor<1, 3>>
    free_stretch_directions(const SamplingSettings &settings,
                            const CoarseElement    &element) const;

    /// The stiffest direction per point of the embedded block under
    /// uniaxial strain (see anisotropy_directions()).
    std::vector<Tensor<1, 3>>
    embedded_stretch_directions(const SamplingSettings &settings,
                                const CoarseElement    &element) const;

    /// The force-space samples of the @p p-th force pattern (see sample()),
    /// drawing standard normal numbers from @p normal.
    void
    force_pattern(const SamplingSettings        &settings,
                  const unsigned int             p,
                  const std::function<double()> &normal,
                  std::vector<Sample>           &samples,
                  unsigned int                  &n_dropped) const;

    /// The embedded samples of the @p p-th embedded pattern (see sample()).
    void
    embedded_pattern(const SamplingSettings        &settings,
                     const unsigned int             p,
                     const std::function<double()> &normal,
                     std::vector<Sample>           &samples,
                     unsigned int                  &n_dropped) const;

    /// The largest value of @p measure(F) over the Gauss points of the
    /// block's solid voxels.
    double
    largest_over_points(
      const Vector<double>                              &u,
      const std::function<double(const Tensor<2, 3> &)> &measure) const;

    /// Largest |eigenvalue| of the small strain over the block.
    double
    linearized_strain(const Vector<double> &u) const;

    /// Largest principal stretch deviation max |lambda_i - 1|.
    double
    finite_strain(const Vector<double> &u) const;

    /// The sample of the solved block field @p u, labelled @p p.
    Sample
    sample_of(const Vector<double> &u, const unsigned int p) const;

    /// Whether point (octant) @p j of child @p k lies in a solid voxel.
    bool
    solid_octant(const unsigned int k, const unsigned int j) const
    {
      return !materials[k].empty() && (void_octants[k] & (1u << j)) == 0;
    }

    std::array<std::vector<material::MaterialPoint>, 8> materials;
    /// The void voxels of the children (none where children are voxels).
    VoidVoxels                                        void_octants;
    Triangulation<3>                                  triangulation;
    FESystem<3>                                       fe;
    DoFHandler<3>                                     dof_handler;
    std::unique_ptr<FEValues<3>>                      fe_values;
    std::vector<std::vector<types::global_dof_index>> cell_dofs;
    std::vector<unsigned int>                         cell_child;
    std::vector<Point<3>>                             support_points;
    /// The vector component of every degree of freedom.
    std::vector<unsigned int> dof_component;
    /// The x/y/z degrees of freedom of every node.
    std::vector<std::array<types::global_dof_index, 3>> node_dofs;
    unsigned int                                        n_components = 0;
    /// Constraint rows G (the zero-energy modes at rest), orthonormalized.
    FullMatrix<double> constraints;
    /// A quarter of a child's face on the block's surface: the face's
    /// vertex it lies at, the outward normal, the vertex's x/y/z dofs.
    struct SurfaceQuarter
    {
      Point<3>                               vertex;
      Tensor<1, 3>                           normal;
      std::array<types::global_dof_index, 3> dofs;
    };
    /// The quarters that force patterns load: those of solid voxels, or,
    /// if these admit no self-equilibrated force, all of them.
    std::vector<SurfaceQuarter> surface_quarters;
    /// The constraint rows restricted to the loaded degrees of freedom
    /// (those of surface_quarters), orthonormalized: a pattern's resultant
    /// force and moment (and a hinge's) are removed over the nodes it
    /// loads, so the nodes it does not load stay free of force.
    FullMatrix<double> load_constraints;
    /// Per corner, its x/y/z dofs or none (a void voxel at the corner).
    std::array<std::array<int, 3>, 8> corner_dofs;
    /// Least-squares trilinear fit: corner value = sum_n weights(v, n) u_n
    /// over the nodes n.
    FullMatrix<double> corner_weights;
    /// Per degree of freedom, its fluctuation unknown, or -1 at corners.
    std::vector<int> periodic_dof;
    /// Number of fluctuation unknowns.
    unsigned int n_periodic = 0;
    /// The stiffness at zero displacement, factorized with constraints.
    LAPACKFullMatrix<double> initial_saddle;
  };
} // namespace ddfem::coarsening

#endif
