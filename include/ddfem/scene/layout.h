#ifndef ddfem_scene_layout_h
#define ddfem_scene_layout_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>

#include <ddfem/scene/voxel_grid.h>

#include <string>
#include <vector>

namespace ddfem::scene
{
  using namespace dealii;

  /**
   * How material ids are laid out in the voxel grid: a base layout
   * (uniform, layers, skin, helical fibers, random, a voxel file, or a
   * voxelized surface mesh) followed by a list of primitive shapes painted
   * over it in order. All lengths are in meters; a voxel belongs to a region
   * when its center does. Declared in the prm subsection "Layout".
   */
  class Layout
  {
  public:
    /// Declares the subsection "Layout" and its sub-subsections.
    static void
    declare_parameters(ParameterHandler &prm);

    /**
     * Reads the subsection "Layout". Material ids are checked against
     * @p n_materials (ids 0 ... n_materials are valid, 0 is void).
     */
    void
    parse_parameters(ParameterHandler &prm, const unsigned int n_materials);

    /// Fills every voxel of @p grid according to this layout.
    void
    fill(VoxelGrid &grid) const;

    /// Number of material edits ('Edits').
    unsigned int
    n_edits() const
    {
      return edits.size();
    }

    /**
     * Applies material edit @p e (from 0) to @p grid and returns the linear
     * indices of the voxels whose id changed. Throws ExcMessage naming the
     * edit: if it would make a voxel void or solid (naming the voxel), if
     * it changes no voxel, or if one of its shapes holds no voxel center or
     * is painted over entirely (as 'Shapes' are checked).
     */
    std::vector<std::size_t>
    apply_edit(const unsigned int e, VoxelGrid &grid) const;

  private:
    /// A primitive painted over the base layout.
    struct Shape
    {
      /// box: lower/upper corner; sphere: center, radius; cylinder: axis
      /// end points a, b and radius.
      enum class Kind
      {
        box,
        sphere,
        cylinder
      } kind;
      std::vector<double> values;
      MaterialId          material;
      /// Its parameter and entry, for messages.
      std::string where;

      /// Whether @p p lies inside this shape or within @p tolerance (m) of
      /// its surface.
      bool
      contains(const Point<3> &p, const double tolerance) const;
    };

    /// Parses the "Shapes" list.
    static std::vector<Shape>
    parse_shapes(const std::string &text,
                 const unsigned int n_materials,
                 const std::string &parameter);

    /// Paints @p list over @p grid in order. A shape that contains no
    /// voxel center is an error: it would paint nothing; so is one whose
    /// every voxel later shapes of @p list give another material.
    static void
    paint(const std::vector<Shape> &list, VoxelGrid &grid);

    /// 'Type' and 'Material' (also core, matrix and inside material).
    std::string type;
    MaterialId  material;

    /// Settings of the layers, skin, fibers, random, voxel file and
    /// surface mesh layouts, in the units of their parameters; ids are
    /// checked only for the active layout.
    unsigned int            layer_axis;
    double                  layer_thickness;
    std::vector<MaterialId> layer_materials;

    double                   skin_thickness;
    std::vector<std::string> skin_faces;
    MaterialId               skin_material;

    unsigned int fiber_axis;
    unsigned int fiber_count;
    double       fiber_radius;
    double       helix_radius;
    double       fiber_pitch;
    MaterialId   fiber_material;

    unsigned int            random_seed;
    std::vector<MaterialId> random_materials;

    std::string  voxel_file;
    unsigned int n_materials;

    std::string surface_file;
    bool        fit_surface;

    /// 'Shapes', painted in this order.
    std::vector<Shape> shapes;
    /// 'Edits': lists of shapes applied one after the other.
    std::vector<std::vector<Shape>> edits;
  };
} // namespace ddfem::scene

#endif
