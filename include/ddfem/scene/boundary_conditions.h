#ifndef ddfem_scene_boundary_conditions_h
#define ddfem_scene_boundary_conditions_h

#include <deal.II/base/function_parser.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>

#include <memory>
#include <string>
#include <vector>

namespace ddfem::scene
{
  using namespace dealii;

  /**
   * A part of the scene's boundary: one face of the grid's bounding box
   * ("x-", "x+", "y-", "y+", "z-", "z+") or the points inside an
   * axis-aligned box "box x0 y0 z0 x1 y1 z1" (meters).
   */
  struct Region
  {
    /**
     * Parses @p text; @p extent is the far corner of the grid's bounding
     * box (the near corner is the origin) and @p h the voxel size, used for
     * the geometric tolerance. @p where names the parameter in messages.
     */
    Region(const std::string &text,
           const Point<3>    &extent,
           const double       h,
           const std::string &where);

    /// Whether @p p lies in the region (within a tolerance of 1e-6 h).
    bool
    contains(const Point<3> &p) const;

    /// The outward unit normal of a face region; zero for a box.
    Tensor<1, 3>
    face_normal() const;

    /// Center of the part of the region inside the grid's bounding box (a
    /// box may reach past the grid to hold all nodes of a face).
    Point<3>
    center() const;

    /// The text the region was parsed from.
    std::string name;
    /// True for a face of the bounding box, false for a box.
    bool is_face;
    /// Lower and upper corner (a degenerate box for a face).
    Point<3> lower, upper;
    /// Geometric tolerance (m).
    double tolerance;
    /// The far corner of the grid's bounding box.
    Point<3> extent;
  };

  /// A boundary face of the solid's voxels, where tractions and pressures
  /// act.
  struct BoundaryFace
  {
    /// Its center.
    Point<3> center;
    /// Its outward unit normal, along one axis.
    Tensor<1, 3> normal;
    /// Its side length (the voxel size, m).
    double size;

    /// The nodes an element of degree @p degree (1 or 2) has on it: its
    /// corners, and at degree 2 its edge midpoints and center too.
    std::vector<Point<3>>
    node_points(const unsigned int degree) const;

    /// The points of the @p n x @p n Gauss rule on it, where an element of
    /// degree n - 1 evaluates a load.
    std::vector<Point<3>>
    gauss_points(const unsigned int n) const;

  private:
    /// The points (u_i, u_j) of the face, with the coordinates @p unit in
    /// [0, 1] along each of its two sides.
    std::vector<Point<3>>
    points(const std::vector<double> &unit) const;
  };

  /**
   * The boundary conditions and loads of a scene. Up to
   * BoundaryConditions::max_conditions conditions are declared in the
   * subsections "Boundary conditions/Condition 1" ... "Condition 8"; each
   * is one of: fixed, sliding (zero normal displacement on a face),
   * prescribed displacement, prescribed rotation about an axis, traction
   * and pressure (dead loads in the reference configuration). A body force
   * is declared in "Loads". Every load and prescribed motion is scaled by
   * the load factor t in [0, 1] the solver steps through (rotations by
   * their angle).
   */
  class BoundaryConditions
  {
  public:
    /// Number of condition slots in the parameter file.
    static constexpr unsigned int max_conditions = 8;

    /// Declares the subsections "Boundary conditions" and "Loads".
    static void
    declare_parameters(ParameterHandler &prm);

    /**
     * Reads and validates the conditions. @p extent is the far corner of
     * the grid's bounding box, @p h the voxel size.
     */
    void
    parse_parameters(ParameterHandler &prm,
                     const Point<3>   &extent,
                     const double      h);

    /// Whether a Dirichlet condition prescribes component @p component
    /// at @p p (without evaluating its value).
    bool
    prescribes(const Point<3> &p, const unsigned int component) const;

    /**
     * Prescribed displacement component @p component at the reference
     * point @p p at load factor @p t: the value of the highest-numbered
     * Dirichlet condition that prescribes it there (later conditions
     * override earlier ones, whose values are not evaluated). Returns false
     * if no condition constrains this component there.
     */
    bool
    prescribed_displacement(const Point<3>    &p,
                            const unsigned int component,
                            const double       t,
                            double            &value) const;

    /**
     * The sum of the traction and pressure loads (Pa) at load factor 1 on
     * a boundary face with center @p face_center, at the point @p p with
     * outward unit normal @p normal. Zero where no such condition applies.
     */
    Tensor<1, 3>
    traction(const Point<3>     &face_center,
             const Point<3>     &p,
             const Tensor<1, 3> &normal) const;

    /**
     * Throws ExcMessage naming the condition if the region of a Dirichlet
     * condition contains none of @p nodes, or the region of a traction or
     * pressure condition the center of none of @p boundary_faces: such a
     * condition would silently do nothing.
     *
     * Where Dirichlet conditions act weakly, @p nodes are the quadrature
     * points of faces, and @p vertices the solid's vertices: a condition
     * that holds vertices but no such point is told so, for its region
     * meets the solid.
     */
    void
    check_regions(const std::vector<Point<3>>     &nodes,
                  const std::vector<BoundaryFace> &boundary_faces,
                  const std::vector<Point<3>>     &vertices = {}) const;

    /**
     * Throws ExcMessage naming the condition if, where its region meets
     * the solid (check_regions()), a condition would still do nothing: a
     * traction or pressure, not zero on its faces among @p boundary_faces,
     * that would go into the reactions whole (and, unless @p weak, a body
     * force, not zero at some of @p nodes, on components held at all of
     * them); or a Dirichlet condition
     * whose every component, at every one of @p nodes it holds, a
     * higher-numbered condition prescribes too (the highest number wins).
     *
     * The load is taken where an element of degree @p degree evaluates it,
     * at the Gauss points of each face (BoundaryFace::gauss_points()). A
     * component of it moves the part if it is not zero at one of a face's
     * Gauss points and some node of that face (BoundaryFace::node_points())
     * is free in that component: the node's shape function carries it
     * there. With @p weak, Dirichlet conditions act at the Gauss points
     * instead, where they take the load's held components off: a component
     * moves the part if it is not zero at a Gauss point where it is free.
     */
    void
    check_effects(const std::vector<Point<3>>     &nodes,
                  const std::vector<BoundaryFace> &boundary_faces,
                  const unsigned int               degree,
                  const bool                       weak) const;

    /**
     * Throws ExcMessage naming the condition and @p parameter if a rotation
     * turns by more than 90 degrees in one of @p load_steps equal load
     * steps. A step prescribes only where each node ends, which carries no
     * winding (a turn of 360 degrees looks like none), and the first step's
     * first iterate moves the turned face along the chords of its nodes' arcs,
     * which squeezes a twisted bar midway to det F = cos^2(theta / 2) for a
     * step of theta: 0.5 at 90 degrees, 0.002 at 175, where the fine solver
     * and corotated DG settled in states that were no solution of the
     * turn (doc/fine_solver.md).
     */
    void
    check_rotation_steps(const unsigned int load_steps,
                         const std::string &parameter) const;

    /**
     * For a coarse model whose blocks span @p width voxels of size @p h per
     * direction, in a grid with the far corner @p extent: throws
     * ExcMessage naming the condition and the bounds to move if a
     * Dirichlet condition on a box region would hold the coarse model at
     * other places than the fine one, because along some direction the
     * first or the last plane of voxel-grid nodes inside the box is not a
     * plane of coarse nodes (a multiple of @p width @p h). Face regions
     * hold the same plane at every level; a partly void block on a held
     * face is held at all four corners there, also where the fine model
     * has no node (doc/coarsening.md, "Supports").
     */
    void
    check_coarse_supports(const Point<3>    &extent,
                          const double       h,
                          const unsigned int width) const;

    /**
     * For weak Dirichlet conditions (DG/Dirichlet = weak), which hold the
     * quadrature points inside their regions, on the solid voxels of size
     * @p h centred at @p voxel_centers: throws ExcMessage naming the
     * condition and the bound to move if a box region's bound reaches
     * into a layer of voxels past its first quadrature points, whose
     * abscissa in a voxel is @p first (a fraction of @p h, from the side
     * of the box), where a solid voxel of the layer meets the box. Such a
     * box holds part or all of the faces that cross the layer, and takes
     * the body force off its points, where a model with conditions at
     * nodes holds only the nodes on the layer's near plane. A bound on a
     * node plane, or short of the first points, holds that plane, as
     * nodes do.
     */
    void
    check_weak_supports(const std::vector<Point<3>> &voxel_centers,
                        const double                 h,
                        const double                 first) const;

    /// Whether any traction or pressure condition is given.
    bool
    has_traction() const;

    /// Body force (N/m^3) at load factor 1 at the reference point @p p.
    Tensor<1, 3>
    body_force(const Point<3> &p) const;

    /// Whether a component of the body force is given as other than "0"
    /// (an expression that is zero everywhere counts as given).
    bool
    has_body_force() const
    {
      return body_force_given;
    }

  private:
    /// One parsed condition.
    struct Condition
    {
      /// The prm subsection, for messages.
      std::string where;
      /// fixed, sliding, displacement, rotation, traction or pressure.
      std::string type;
      /// Where it applies.
      std::unique_ptr<Region> region;
      /// Displacement, traction or pressure expressions.
      std::unique_ptr<FunctionParser<3>> value;
      /// Dirichlet conditions: which components they prescribe.
      std::vector<bool> constrained;
      /// rotation: the unit axis.
      Tensor<1, 3> axis;
      /// rotation: a point on the axis.
      Point<3> center;
      /// rotation: the angle at t = 1 (radians).
      double angle = 0;

      /// Whether this is a Dirichlet condition that prescribes component
      /// @p component at @p p.
      bool
      prescribes(const Point<3> &p, const unsigned int component) const;

      /// The condition for messages: its subsection, type and region, as
      /// in 'Boundary conditions/Condition 2 (fixed on "z-")'.
      std::string
      describe() const
      {
        return where + " (" + type + " on \"" + region->name + "\")";
      }
    };

    /// The highest-numbered Dirichlet condition that prescribes component
    /// @p component at @p p, whose value the component takes; nullptr if
    /// none does.
    const Condition *
    holding_condition(const Point<3> &p, const unsigned int component) const;

    /// The load (Pa) of the traction or pressure @p condition at the point
    /// @p p of a face with outward unit normal @p normal, at load factor 1.
    static Tensor<1, 3>
    load(const Condition    &condition,
         const Point<3>     &p,
         const Tensor<1, 3> &normal);

    /// The conditions in prm order (later ones override earlier ones).
    std::vector<Condition> conditions;
    /// Body force expressions (N/m^3).
    std::unique_ptr<FunctionParser<3>> body;
    /// Whether the body force is given as anything but "0; 0; 0".
    bool body_force_given = false;
  };
} // namespace ddfem::scene

#endif
