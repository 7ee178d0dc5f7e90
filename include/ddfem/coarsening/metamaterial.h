#ifndef ddfem_coarsening_metamaterial_h
#define ddfem_coarsening_metamaterial_h

#include <deal.II/base/quadrature.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/tria.h>

#include <ddfem/coarsening/symmetry.h>
#include <ddfem/material/kernel.h>
#include <ddfem/solver/discretization.h>

#include <array>
#include <memory>
#include <optional>
#include <vector>

namespace ddfem::coarsening
{
  using namespace dealii;

  /**
   * The displacements of the eight corners of a block (or of one coarse
   * hex), in deal.II's lexicographic vertex order: corner v sits at
   * (v & 1, (v >> 1) & 1, (v >> 2) & 1) of the unit cube.
   */
  using CornerDisplacements = std::array<Tensor<1, 3>, 8>;

  /**
   * A metamaterial: the material record of every quadrature point of one
   * coarse element (paper eq. 2). Level 1 has 8 points, point k in octant
   * k; level 2 has 64, one per voxel of the 4x4x4 block (see
   * solver::coarse_quadrature(): the 2-point Gauss rule, iterated at level
   * 2, moved toward the centre by the level's point offset).
   */
  struct Metamaterial
  {
    /// One material record per quadrature point of the coarse element.
    std::vector<material::MaterialPoint> points;

    /**
     * The smallest shear modulus a point of this element may have, as a
     * void point of the naive element or as a fitted value: @p fraction
     * of the largest mu of the solid points (mu > 0; void points have
     * mu = 0), but never more than the smallest. Beyond a stiffness
     * contrast of 1 / @p fraction a fraction of the largest mu would make
     * void, or a fitted soft point, stiffer than the block's softest
     * material.
     */
    double
    stiffness_floor(const double fraction) const;
  };

  /// The default fraction for Metamaterial::stiffness_floor(): the
  /// fitter's default 'Stiffness floor' and the naive element's void
  /// stiffness.
  constexpr double default_stiffness_floor = 1e-3;

  /**
   * The image of a level-1 metamaterial under cube symmetry @p g: the
   * record of point k moves to point image(g, k) and its direction turns
   * with the symmetry's matrix.
   */
  Metamaterial
  transform(const Metamaterial   &m,
            const CubeSymmetries &symmetries,
            const unsigned int    g);

  /**
   * How the symmetries of a level-1 block tie the parameters of its fit
   * (MetamaterialFit). Empty vectors tie nothing: every point is its own
   * class and has a spring.
   */
  struct PointTies
  {
    /// The class of every point: its orbit under the symmetries that keep
    /// the block's combination. Points of one class share mu, lambda and C.
    std::vector<unsigned int> point_class;
    /// Whether each point has a spring (false: C = 0, not fitted).
    std::vector<bool> has_spring;
  };

  /**
   * Makes the spring directions of the level-1 metamaterial @p m symmetric
   * under the symmetries that leave its @p combination unchanged (its
   * stabilizer) and returns how they tie the fit. Each point's direction
   * becomes the principal axis of the average of v v^T over the
   * stabilizer's images. Where the largest eigenvalue of that average is
   * double, no line is kept by the point's symmetries (the corner points
   * of a homogeneous block, whose stretch-test springs span the plane
   * normal to the cube's diagonal, or all directions): the point gets no
   * spring; its stored direction is then a unit vector of that eigenspace
   * that the eigensolver's round-off picks. Level 2 starts each of its
   * points from its child's direction and fits a spring there too: on a
   * homogeneous 4x4x4 block, whose children have no springs, it came to
   * C of about 1e-4 mu (doc/metamaterial_database.md, "Compression and
   * the second level"). A fit with these directions and ties gives a
   * symmetric block an exactly symmetric metamaterial, the best one of its
   * samples among the symmetric ones, so the lookup does not depend on
   * which symmetry maps the orbit's entry.
   */
  PointTies
  symmetrize_directions(Metamaterial         &m,
                        const Combination    &combination,
                        const CubeSymmetries &symmetries);

  /**
   * The axis normal to the plane that splits the block @p combination into
   * two halves of one material each, different from each other: two layers
   * one voxel thick, or a layer on void. None for any other block.
   */
  std::optional<unsigned int>
  split_axis(const Combination &combination);

  /**
   * Spring directions and ties of a block split by the plane normal to
   * @p axis (split_axis()) into two layers. Such a block is a laminate,
   * stiff along the plane and soft across it. The stretch test gives its
   * points no line in the plane (all in-plane directions are alike), and
   * the only lines the block's mirror symmetries keep, the plane's
   * diagonals and its normal, cannot make a stretch along the plane's axes
   * stiff without making the block stiff across. Here the four points of
   * the softer half (smaller mu, then smaller lambda, of the points of @p m;
   * void is softer than any material) get springs along the plane's two
   * axes and the four of the stiffer half along the plane's two diagonals,
   * alternating from point to point: stretch and shear in the plane both
   * meet springs. Each half's points form one class of the fit. The
   * pattern follows the materials, not the side of the plane: the block
   * mirrored across the plane gets the mirrored pattern, so a fit does not
   * depend on the orientation of its orbit's representative, which the
   * palette's order sets. The axes on the stiffer half instead made a
   * cantilever of layers normal to z 14 times less accurate
   * (doc/coarsening.md). The pattern is kept by the block's quarter turns
   * about the normal, so a fit with these ties is exactly symmetric under
   * them. It is not kept by the mirrors across planes through the normal:
   * a lookup through one returns the mirrored pattern, which has the same
   * energy under every homogeneous deformation.
   *
   * Used with 'Database/Fitting/Laminate springs' (FitSettings); without
   * it, split blocks keep the springs of symmetrize_directions().
   */
  PointTies
  laminate_springs(Metamaterial &m, const unsigned int axis);

  /**
   * One coarse element on the unit cube, trilinear (FE_Q(1)^3), with the
   * quadrature of a coarsening level, solver::coarse_quadrature(): 8
   * points, one per child octant, at level 1, 64 points, one per voxel, at
   * level 2 (the 2-point Gauss rule and that rule iterated twice, moved
   * toward the centre by the point offset). It
   * evaluates metamaterial energies through the cell kernel the solvers
   * use, and the per-point energy terms the fitter needs. Energies are per
   * unit volume of the coarse element: metamaterial parameters do not
   * depend on the voxel size.
   *
   * All evaluation functions are const and thread safe.
   */
  class CoarseElement
  {
  public:
    /// Sets up the element for coarsening level 1 or 2 with the points of
    /// solver::coarse_quadrature(@p level, @p point_offset).
    explicit CoarseElement(
      const unsigned int level,
      const double       point_offset = solver::gauss_point_offset);

    /// The offset of the points (see solver::coarse_quadrature()).
    double
    point_offset() const
    {
      return offset;
    }

    /// Number of quadrature points (8 or 64).
    unsigned int
    n_points() const
    {
      return quadrature.size();
    }

    /// The child octant (0..7) quadrature point @p q lies in.
    unsigned int
    child_of_point(const unsigned int q) const
    {
      return point_child[q];
    }

    /**
     * The octant of the child that point @p q lies in, within that child
     * (0..7): the index of the child's own 2-point Gauss point at level 2;
     * 0 at level 1 (one point per child).
     */
    unsigned int
    subpoint_of_point(const unsigned int q) const
    {
      return point_subindex[q];
    }

    /// The quadrature point @p q in unit-cube coordinates.
    const Point<3> &
    point(const unsigned int q) const
    {
      return quadrature.point(q);
    }

    /// The deformation gradient at every quadrature point.
    void
    deformation_gradients(const CornerDisplacements &u,
                          std::vector<Tensor<2, 3>> &F) const;

    /**
     * The energy of the element with metamaterial @p m under corner
     * displacements @p u. Returns false if det F <= 0 at a point.
     */
    bool
    energy(const CornerDisplacements &u,
           const Metamaterial        &m,
           double                    &energy) const;

    /**
     * The energy of the element is linear in the parameters (mu, lambda,
     * C) of its points: E = sum_q mu_q a_q + lambda_q b_q + C_q c_q. This
     * fills @p terms with (a_q, b_q, c_q), quadrature weight included, for
     * the directions of @p m (its parameters are ignored). Returns false
     * if det F <= 0 at a point.
     */
    bool
    energy_terms(const CornerDisplacements          &u,
                 const Metamaterial                 &m,
                 std::vector<std::array<double, 3>> &terms) const;

  private:
    /// Corner displacements as the element's local coefficient vector.
    Vector<double>
    local_vector(const CornerDisplacements &u) const;

    Triangulation<3>             triangulation;
    FESystem<3>                  fe;
    DoFHandler<3>                dof_handler;
    double                       offset;
    Quadrature<3>                quadrature;
    std::unique_ptr<FEValues<3>> fe_values;
    std::vector<unsigned int>    point_child;
    std::vector<unsigned int>    point_subindex;
  };
} // namespace ddfem::coarsening

#endif
