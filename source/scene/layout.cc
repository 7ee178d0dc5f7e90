#include <deal.II/base/utilities.h>

#include <ddfem/base/exceptions.h>
#include <ddfem/base/parsing.h>
#include <ddfem/scene/layout.h>
#include <ddfem/scene/voxel_io.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

namespace ddfem::scene
{
  namespace
  {
    /// Index of axis name "x", "y" or "z".
    unsigned int
    axis_index(const std::string &name)
    {
      return name == "x" ? 0 : (name == "y" ? 1 : 2);
    }

    /// The error for the material id @p id (as given in @p where) outside
    /// a palette of @p n_materials materials.
    ExcMessage
    not_in_palette(const std::string &id,
                   const unsigned int n_materials,
                   const std::string &where)
    {
      return ExcMessage(where + ": material id " + id +
                        " is not in the palette; allowed are 0 (void) to " +
                        std::to_string(n_materials) + ".");
    }

    /// Converts @p value to a material id, checking it against the palette.
    MaterialId
    checked_id(const long         value,
               const unsigned int n_materials,
               const std::string &where)
    {
      AssertThrow(value >= 0 && value <= static_cast<long>(n_materials),
                  not_in_palette(std::to_string(value), n_materials, where));
      return static_cast<MaterialId>(value);
    }

    /// Converts a list of integers to checked material ids.
    std::vector<MaterialId>
    checked_ids(const std::string &list,
                const unsigned int n_materials,
                const std::string &where)
    {
      std::vector<MaterialId> ids;
      for (const int v : Utilities::string_to_int(split_list(list, ',', where)))
        ids.push_back(checked_id(v, n_materials, where));
      AssertThrow(!ids.empty(),
                  ExcMessage(where + " must list at least one material id."));
      return ids;
    }
  } // namespace



  void
  Layout::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Layout");
    {
      prm.declare_entry(
        "Type",
        "uniform",
        Patterns::Selection(
          "uniform|layers|skin|fibers|random|voxel file|surface mesh"),
        "The base layout of material ids. 'uniform' fills every voxel "
        "with 'Material'; the others are described in the subsection "
        "of the same name. 'Shapes' are painted over the base layout.");
      prm.declare_entry(
        "Material",
        "1",
        Patterns::Integer(0, 254),
        "Material id of the uniform layout, and of the core, matrix or "
        "inside of the skin, fibers and surface mesh layouts (0 = void, "
        "but not inside a surface mesh). The other layouts ignore it.");
      prm.declare_entry(
        "Shapes",
        "",
        Patterns::Anything(),
        "Primitives painted over the base layout in the order given, separated by "
        "';'. Each is 'box x0 y0 z0 x1 y1 z1 : id', 'sphere cx cy cz r : id' or "
        "'cylinder ax ay az bx by bz r : id' (a cylinder of radius r around the "
        "segment from a to b). Coordinates in meters; a voxel takes the id if its "
        "center lies inside, or on the surface within 1e-6 of a voxel size (so "
        "that a bound written at a voxel center holds it whatever the "
        "round-off). Each shape must keep its material in a voxel: one whose "
        "every voxel later shapes give another material is an error.");
      prm.declare_entry(
        "Edits",
        "",
        Patterns::Anything(),
        "Material edits applied after the layout, in sequence, separated by "
        "'|': each is a list of primitives in the syntax of 'Shapes'. An edit "
        "may only change which material a solid voxel has (never make a "
        "voxel void or solid), so the mesh stays the same and coarse models "
        "re-coarsen only the blocks it touched. A simulation solves the "
        "scene before the first edit and after each one (not with Method "
        "= dg, which refuses edits). An edit must change a voxel.");

      prm.enter_subsection("Layers");
      prm.declare_entry("Axis",
                        "y",
                        Patterns::Selection("x|y|z"),
                        "Axis the layers stack along.");
      prm.declare_entry(
        "Thickness",
        "0.01",
        Patterns::Double(0),
        "Thickness of one layer (m): at least the voxel size, and best a "
        "multiple of it. A voxel whose center lies on a layer boundary "
        "takes the layer above it.");
      prm.declare_entry(
        "Materials",
        "1, 3",
        Patterns::List(Patterns::Integer(0, 254), 1),
        "Material ids of consecutive layers, repeated cyclically.");
      prm.leave_subsection();

      prm.enter_subsection("Skin");
      prm.declare_entry("Thickness",
                        "0.01",
                        Patterns::Double(0),
                        "Skin thickness (m): voxels whose centers lie "
                        "closer than this to a skin face take the skin "
                        "material (a center at exactly this distance does "
                        "not).");
      prm.declare_entry(
        "Faces",
        "all",
        Patterns::List(Patterns::Selection("all|x-|x+|y-|y+|z-|z+")),
        "Faces of the grid's bounding box that carry the skin.");
      prm.declare_entry("Skin material",
                        "3",
                        Patterns::Integer(0, 254),
                        "Material id of the skin.");
      prm.leave_subsection();

      prm.enter_subsection("Fibers");
      prm.declare_entry("Axis",
                        "y",
                        Patterns::Selection("x|y|z"),
                        "Axis of the bar the fibers wind around.");
      prm.declare_entry("Count",
                        "4",
                        Patterns::Integer(1, 1000),
                        "Number of helical fibers.");
      prm.declare_entry("Fiber radius",
                        "0.02",
                        Patterns::Double(0),
                        "Radius of each fiber (m).");
      prm.declare_entry(
        "Helix radius",
        "0.08",
        Patterns::Double(0),
        "Distance of each fiber's center line from the bar's axis (m).");
      prm.declare_entry(
        "Pitch",
        "1",
        Patterns::Double(0),
        "Length along the axis of one full turn of a fiber (m).");
      prm.declare_entry("Fiber material",
                        "3",
                        Patterns::Integer(0, 254),
                        "Material id of the fibers.");
      prm.leave_subsection();

      prm.enter_subsection("Random");
      prm.declare_entry("Seed",
                        "1",
                        Patterns::Integer(0),
                        "Seed of the random layout.");
      prm.declare_entry(
        "Materials",
        "1, 2, 3",
        Patterns::List(Patterns::Integer(0, 254), 1),
        "Material ids drawn with equal probability for each voxel.");
      prm.leave_subsection();

      prm.enter_subsection("Voxel file");
      prm.declare_entry(
        "File name",
        "",
        Patterns::FileName(),
        "Text file: a header 'nx ny nz' equal to the grid size, then "
        "nx*ny*nz material ids, x fastest, then y, then z. A '#' starts a "
        "comment that runs to the end of its line.");
      prm.leave_subsection();

      prm.enter_subsection("Surface mesh");
      prm.declare_entry(
        "File name",
        "",
        Patterns::FileName(),
        "Closed triangle surface (.stl ASCII or binary, or .obj). Voxels "
        "whose centers lie inside get 'Material', all others are void. "
        "Overlapping closed bodies make their union: each shell is oriented "
        "as most of its triangles are (a few reversed triangles are "
        "repaired; a cavity's shell must face inward, as exporters write "
        "it), and a point is inside where its winding number is not 0. A "
        "mesh that cannot be oriented falls back to parity (a point inside "
        "two shells counts as outside).");
      prm.declare_entry(
        "Fit to grid",
        "true",
        Patterns::Bool(),
        "Scale and center the mesh uniformly to fill the grid's bounding "
        "box; if false, mesh coordinates are taken as meters and must lie "
        "in the grid (within half a voxel).");
      prm.leave_subsection();
    }
    prm.leave_subsection();
  }



  void
  Layout::parse_parameters(ParameterHandler &prm, const unsigned int n_mat)
  {
    n_materials = n_mat;
    prm.enter_subsection("Layout");
    {
      type = prm.get("Type");
      // Only these types read 'Material'; the others ignore it.
      material = (type == "uniform" || type == "skin" || type == "fibers" ||
                  type == "surface mesh") ?
                   checked_id(prm.get_integer("Material"),
                              n_materials,
                              "Layout/Material") :
                   void_id;
      AssertThrow(type != "surface mesh" || material != void_id,
                  ExcMessage("Layout/Material = 0 (void) would leave the "
                             "inside of the surface mesh void: give the "
                             "material id of its inside, 1 to " +
                             std::to_string(n_materials) + "."));
      shapes = parse_shapes(prm.get("Shapes"), n_materials, "Layout/Shapes");
      edits.clear();
      // split_list() rejects an empty edit, so each has a shape.
      for (const std::string &edit :
           split_list(prm.get("Edits"), '|', "Layout/Edits"))
        edits.push_back(parse_shapes(edit,
                                     n_materials,
                                     "Layout/Edits, edit " +
                                       std::to_string(edits.size() + 1)));

      prm.enter_subsection("Layers");
      layer_axis      = axis_index(prm.get("Axis"));
      layer_thickness = prm.get_double("Thickness");
      if (type == "layers")
        layer_materials = checked_ids(prm.get("Materials"),
                                      n_materials,
                                      "Layout/Layers/Materials");
      prm.leave_subsection();

      prm.enter_subsection("Skin");
      skin_thickness = prm.get_double("Thickness");
      skin_faces     = split_list(prm.get("Faces"), ',', "Layout/Skin/Faces");
      if (type == "skin")
        {
          skin_material = checked_id(prm.get_integer("Skin material"),
                                     n_materials,
                                     "Layout/Skin/Skin material");
          AssertThrow(!skin_faces.empty(),
                      ExcMessage("Layout/Skin/Faces is empty: name the faces "
                                 "that carry the skin (all, x-, x+, y-, y+, "
                                 "z-, z+)."));
        }
      prm.leave_subsection();

      prm.enter_subsection("Fibers");
      fiber_axis   = axis_index(prm.get("Axis"));
      fiber_count  = prm.get_integer("Count");
      fiber_radius = prm.get_double("Fiber radius");
      helix_radius = prm.get_double("Helix radius");
      fiber_pitch  = prm.get_double("Pitch");
      if (type == "fibers")
        fiber_material = checked_id(prm.get_integer("Fiber material"),
                                    n_materials,
                                    "Layout/Fibers/Fiber material");
      prm.leave_subsection();

      prm.enter_subsection("Random");
      random_seed = prm.get_integer("Seed");
      if (type == "random")
        random_materials = checked_ids(prm.get("Materials"),
                                       n_materials,
                                       "Layout/Random/Materials");
      prm.leave_subsection();

      prm.enter_subsection("Voxel file");
      voxel_file = prm.get("File name");
      prm.leave_subsection();

      prm.enter_subsection("Surface mesh");
      surface_file = prm.get("File name");
      fit_surface  = prm.get_bool("Fit to grid");
      prm.leave_subsection();
    }
    prm.leave_subsection();

    // The smallest voxel size: anything thinner aliases.
    AssertThrow(type != "layers" || layer_thickness >= 1e-6,
                ExcMessage("Layout/Layers/Thickness must be at least 1e-6 m."));
    AssertThrow(type != "fibers" || fiber_pitch >= 1e-6,
                ExcMessage("Layout/Fibers/Pitch must be at least 1e-6 m."));
    // A skin or fibers of zero size would silently paint nothing.
    AssertThrow(type != "skin" || skin_thickness >= 1e-6,
                ExcMessage("Layout/Skin/Thickness must be at least 1e-6 m."));
    AssertThrow(type != "fibers" || fiber_radius >= 1e-6,
                ExcMessage(
                  "Layout/Fibers/Fiber radius must be at least 1e-6 m."));
    AssertThrow(
      type != "voxel file" || !voxel_file.empty(),
      ExcMessage(
        "Layout/Voxel file/File name must be set for 'Type = voxel file'."));
    AssertThrow(
      type != "surface mesh" || !surface_file.empty(),
      ExcMessage(
        "Layout/Surface mesh/File name must be set for 'Type = surface mesh'."));
  }



  std::vector<Layout::Shape>
  Layout::parse_shapes(const std::string &text,
                       const unsigned int n_materials,
                       const std::string &parameter)
  {
    std::vector<Shape> result;
    for (const std::string &entry : split_list(text, ';', parameter))
      {
        const std::string where = parameter + ", entry \"" + entry + "\"";
        const auto        parts = split_list(entry, ':', parameter);
        AssertThrow(
          parts.size() == 2,
          ExcMessage(where + ": expected '<kind> <numbers> : <material id>'."));
        auto words = split_words(parts[0]);
        AssertThrow(!words.empty(),
                    ExcMessage(where + ": missing shape kind."));

        Shape        shape;
        unsigned int expected = 0;
        if (words[0] == "box")
          shape.kind = Shape::Kind::box, expected = 6;
        else if (words[0] == "sphere")
          shape.kind = Shape::Kind::sphere, expected = 4;
        else if (words[0] == "cylinder")
          shape.kind = Shape::Kind::cylinder, expected = 7;
        else
          AssertThrow(false,
                      ExcMessage(where + ": unknown shape '" + words[0] +
                                 "'; allowed are box, sphere, cylinder."));
        words.erase(words.begin());
        AssertThrow(words.size() == expected,
                    ExcMessage(where + ": '" + parts[0] + "' needs " +
                               std::to_string(expected) + " numbers."));
        for (const std::string &word : words)
          shape.values.push_back(parse_number(word, where));
        const auto &v   = shape.values;
        const bool  box = (shape.kind == Shape::Kind::box);
        AssertThrow(!box || (v[0] <= v[3] && v[1] <= v[4] && v[2] <= v[5]),
                    ExcMessage(
                      where +
                      ": the lower corner must not exceed the upper one."));
        AssertThrow(box || v.back() > 0,
                    ExcMessage(where + ": the radius must be > 0."));
        // contains() divides by the axis' squared length.
        const double axis2 =
          shape.kind == Shape::Kind::cylinder ?
            Point<3>(v[3] - v[0], v[4] - v[1], v[5] - v[2]).norm_square() :
            1.;
        AssertThrow(axis2 > 0 && std::isfinite(axis2),
                    ExcMessage(where + ": the axis end points must differ, "
                                       "by less than 1e154 m."));
        const double id = parse_number(parts[1], where);
        AssertThrow(id == std::round(id),
                    ExcMessage(where + ": the material id is not an integer."));
        // Checked as a number: an id too large for an integer is named as
        // given.
        AssertThrow(id >= 0 && id <= n_materials,
                    not_in_palette(Utilities::trim(parts[1]),
                                   n_materials,
                                   where));
        shape.material = static_cast<MaterialId>(id);
        shape.where    = where;
        result.push_back(shape);
      }
    return result;
  }



  bool
  Layout::Shape::contains(const Point<3> &p, const double tolerance) const
  {
    const auto &v = values;
    switch (kind)
      {
        case Kind::box:
          for (unsigned int d = 0; d < 3; ++d)
            if (p[d] < v[d] - tolerance || p[d] > v[d + 3] + tolerance)
              return false;
          return true;
        case Kind::sphere:
          return p.distance(Point<3>(v[0], v[1], v[2])) <= v[3] + tolerance;
        case Kind::cylinder:
          {
            const Point<3>     a(v[0], v[1], v[2]), b(v[3], v[4], v[5]);
            const Tensor<1, 3> axis   = b - a;
            const double       length = axis.norm();
            const double       t      = (p - a) * axis / (length * length);
            return t * length >= -tolerance &&
                   t * length <= length + tolerance &&
                   (p - (a + t * axis)).norm() <= v[6] + tolerance;
          }
      }
    return false;
  }



  void
  Layout::fill(VoxelGrid &grid) const
  {
    const auto    &n      = grid.size();
    const Point<3> extent = grid.extent();
    // The layer of a voxel center at @p x along the layers' axis: a center
    // on a layer boundary takes the layer above it (within 1e-6 of a
    // voxel, as 0.075 / 0.025 is 2.9999999999999996).
    const auto layer_of = [&](const double x) {
      return static_cast<std::size_t>((x + 1e-6 * grid.voxel_size()) /
                                      layer_thickness);
    };

    if (type == "voxel file")
      read_voxel_file(voxel_file, n_materials + 1 /* with void */, grid);
    else if (type == "surface mesh")
      {
        TriangleMesh mesh = read_surface_mesh(surface_file);
        if (fit_surface)
          try
            {
              fit_to_box(mesh, Point<3>(), extent);
            }
          catch (ExceptionBase &e)
            {
              AssertThrow(false,
                          ExcMessage("Surface mesh \"" + surface_file +
                                     "\" (Layout/Surface mesh/File name, "
                                     "Fit to grid = true): " +
                                     message_of(e)));
            }
        else
          {
            // A part reaching out of the grid would be cut off without a
            // word; half a voxel leaves room for a mesh that touches its
            // faces.
            const double h = 0.5 * grid.voxel_size();
            for (const Point<3> &p : mesh.vertices)
              for (unsigned int d = 0; d < 3; ++d)
                AssertThrow(p[d] >= -h && p[d] <= extent[d] + h,
                            ExcMessage(
                              "Surface mesh \"" + surface_file +
                              "\" (Layout/Surface mesh/File name, "
                              "Fit to grid = false): its vertex " +
                              format_point(p) +
                              " lies outside the grid, from (0, 0, 0) to " +
                              format_point(extent) +
                              " m, by more than half a voxel. Move "
                              "or scale the mesh, or set Fit to "
                              "grid = true."));
          }
        grid = VoxelGrid(n, grid.voxel_size(), void_id);
        voxelize(mesh, material, grid);
        // A mesh in other units than meters, or a flat one, would leave
        // the grid void, or only the shapes solid.
        AssertThrow(grid.n_solid_voxels() > 0,
                    ExcMessage("Surface mesh \"" + surface_file +
                               "\" (Layout/Surface mesh/File name): it "
                               "encloses no voxel center of the grid, which "
                               "spans (0, 0, 0) to " +
                               format_point(extent) +
                               " m. Is it closed, with a volume, and in "
                               "meters?"));
      }
    else
      {
        std::mt19937 random(random_seed);
        // The skin's faces, per axis: the low (x-) and the high (x+) one.
        std::array<bool, 3> skin_low{}, skin_high{};
        for (const std::string &face : skin_faces)
          for (unsigned int d = 0; d < 3; ++d)
            {
              const std::string axis(1, "xyz"[d]);
              skin_low[d] = skin_low[d] || face == "all" || face == axis + "-";
              skin_high[d] =
                skin_high[d] || face == "all" || face == axis + "+";
            }
        // Each fiber's center line in the cross-section, per voxel layer
        // along the axis: fiber_centers[layer * fiber_count + f].
        std::vector<Point<2>> fiber_centers;
        if (type == "fibers")
          for (unsigned int layer = 0; layer < n[fiber_axis]; ++layer)
            for (unsigned int f = 0; f < fiber_count; ++f)
              {
                // The voxel centers' coordinate along the axis, computed as
                // VoxelGrid::center() does.
                const double along = (layer + 0.5) * grid.voxel_size();
                const double angle = 2 * numbers::PI * f / fiber_count +
                                     2 * numbers::PI * along / fiber_pitch;
                fiber_centers.emplace_back(helix_radius * std::cos(angle),
                                           helix_radius * std::sin(angle));
              }
        for (unsigned int k = 0; k < n[2]; ++k)
          for (unsigned int j = 0; j < n[1]; ++j)
            for (unsigned int i = 0; i < n[0]; ++i)
              {
                const Point<3> c  = grid.center(i, j, k);
                MaterialId     id = material;
                if (type == "layers")
                  {
                    id = layer_materials[layer_of(c[layer_axis]) %
                                         layer_materials.size()];
                  }
                else if (type == "skin")
                  {
                    // Distances to the faces in voxels, the same
                    // round-off on both sides: a thickness at a voxel
                    // center takes as many voxels on each face, and not
                    // that center's (within 1e-6 of a voxel, as 0.035 /
                    // 0.01 is 3.5000000000000004).
                    const std::array<unsigned int, 3> index{{i, j, k}};
                    const double                      thickness =
                      skin_thickness / grid.voxel_size() - 1e-6;
                    for (unsigned int d = 0; d < 3; ++d)
                      if ((skin_low[d] && index[d] + 0.5 < thickness) ||
                          (skin_high[d] && n[d] - index[d] - 0.5 < thickness))
                        id = skin_material;
                  }
                else if (type == "fibers")
                  {
                    const unsigned int a1 = (fiber_axis + 1) % 3,
                                       a2 = (fiber_axis + 2) % 3;
                    const double       x  = c[a1] - 0.5 * extent[a1];
                    const double       y  = c[a2] - 0.5 * extent[a2];
                    const unsigned int layer =
                      std::array<unsigned int, 3>{{i, j, k}}[fiber_axis];
                    for (unsigned int f = 0; f < fiber_count; ++f)
                      {
                        const Point<2> &center =
                          fiber_centers[layer * fiber_count + f];
                        const double dx = x - center[0];
                        const double dy = y - center[1];
                        if (dx * dx + dy * dy <= fiber_radius * fiber_radius)
                          id = fiber_material;
                      }
                  }
                else if (type == "random")
                  id = random_materials[random() % random_materials.size()];
                grid(i, j, k) = id;
              }
        // A skin thinner than half a voxel, or fibers between the voxel
        // centers, would silently leave the base material alone.
        const MaterialId painted_id =
          (type == "skin" ? skin_material : fiber_material);
        AssertThrow(
          (type != "skin" && type != "fibers") ||
            std::count(grid.data().begin(), grid.data().end(), painted_id) >
              0 ||
            painted_id == material,
          ExcMessage(
            type == "skin" ?
              "Layout/Skin/Thickness = " + format_number(skin_thickness) +
                " m reaches no voxel center (they lie half a voxel, " +
                format_number(0.5 * grid.voxel_size()) +
                " m, in from the faces): the skin would be empty." :
              "Layout/Fibers: no voxel center lies within 'Fiber "
              "radius' of a fiber's axis (check 'Helix radius' "
              "against the grid's cross-section): the fibers "
              "would be empty."));
        // A skin or fibers that cover every voxel leave none of the base
        // material: the part is all skin or fiber.
        AssertThrow(
          (type != "skin" && type != "fibers") || painted_id == material ||
            std::count(grid.data().begin(), grid.data().end(), material) > 0,
          ExcMessage(
            (type == "skin" ?
               "Layout/Skin/Thickness = " + format_number(skin_thickness) +
                 " m covers every voxel" :
               "Layout/Fibers: the fibers of 'Fiber radius' = " +
                 format_number(fiber_radius) + " m cover every voxel") +
            ", so no voxel keeps Layout/Material = " +
            std::to_string(material) +
            ". For a part of one material use Layout/Type = uniform; "
            "otherwise make the " +
            (type == "skin" ? "skin thinner." : "fibers thinner.")));
        // Layers thinner than a voxel would be sampled at the voxel
        // centers, not resolved: each voxel takes the layer at its center.
        // Thicker layers each hold a voxel center, and the grid must hold
        // a layer for each entry of 'Materials'.
        if (type == "layers")
          {
            AssertThrow(layer_thickness >= grid.voxel_size() * (1 - 1e-12),
                        ExcMessage("Layout/Layers/Thickness = " +
                                   format_number(layer_thickness) +
                                   " m is thinner than a voxel "
                                   "(Geometry/Voxel size = " +
                                   format_number(grid.voxel_size()) +
                                   " m): each voxel would take the layer at "
                                   "its center, and the layers would not be "
                                   "resolved. Give layers of at least one "
                                   "voxel."));
            const std::size_t n_layers =
              layer_of(grid.center(n[0] - 1, n[1] - 1, n[2] - 1)[layer_axis]) +
              1;
            AssertThrow(
              layer_materials.size() <= n_layers,
              ExcMessage(
                "Layout/Layers/Materials lists " +
                std::to_string(layer_materials.size()) +
                " materials, but the grid holds " + std::to_string(n_layers) +
                " layer(s) of 'Thickness' = " + format_number(layer_thickness) +
                " m: list at most " + std::to_string(n_layers) + "."));
          }
      }

    paint(shapes, grid);
  }



  void
  Layout::paint(const std::vector<Shape> &list, VoxelGrid &grid)
  {
    const auto &n = grid.size();
    // Per shape: whether it contains a voxel center, and whether one of
    // them keeps its material in the end (later shapes may paint over it).
    std::vector<bool> painted(list.size(), false), kept(list.size(), false);
    std::vector<unsigned int> holding;
    if (!list.empty())
      for (unsigned int k = 0; k < n[2]; ++k)
        for (unsigned int j = 0; j < n[1]; ++j)
          for (unsigned int i = 0; i < n[0]; ++i)
            {
              holding.clear();
              for (unsigned int s = 0; s < list.size(); ++s)
                if (list[s].contains(grid.center(i, j, k),
                                     1e-6 * grid.voxel_size()))
                  {
                    grid(i, j, k) = list[s].material;
                    painted[s]    = true;
                    holding.push_back(s);
                  }
              for (const unsigned int s : holding)
                if (list[s].material == grid(i, j, k))
                  kept[s] = true;
            }
    for (unsigned int s = 0; s < list.size(); ++s)
      {
        AssertThrow(painted[s],
                    ExcMessage(list[s].where +
                               ": the shape contains no voxel center of the "
                               "grid, which spans (0, 0, 0) to " +
                               format_point(grid.extent()) +
                               " m with voxel centers half a voxel in from "
                               "its faces, so it would paint nothing "
                               "(coordinates are meters)."));
        AssertThrow(kept[s],
                    ExcMessage(list[s].where +
                               ": later shapes of the list give every voxel "
                               "of the shape another material, so it has no "
                               "effect (shapes are painted in the order "
                               "given)."));
      }
  }



  std::vector<std::size_t>
  Layout::apply_edit(const unsigned int e, VoxelGrid &grid) const
  {
    AssertIndexRange(e, edits.size());
    const VoxelGrid before = grid;
    paint(edits[e], grid);
    std::vector<std::size_t> changed;
    for (std::size_t v = 0; v < grid.n_voxels(); ++v)
      if (grid[v] != before[v])
        {
          AssertThrow(grid[v] != void_id && before[v] != void_id,
                      ExcMessage(
                        "Layout/Edits, edit " + std::to_string(e + 1) +
                        ": the " + grid.voxel_name(v) +
                        " would change from id " + std::to_string(before[v]) +
                        " to " + std::to_string(grid[v]) +
                        "; edits may only change the material of solid "
                        "voxels (ids 1 and up), not add or remove them."));
          changed.push_back(v);
        }
    AssertThrow(!changed.empty(),
                ExcMessage("Layout/Edits, edit " + std::to_string(e + 1) +
                           ": its shapes give every voxel they contain the "
                           "material it has already, so it changes nothing "
                           "and would only solve the same state again. "
                           "Remove the edit, or change its shapes or "
                           "material."));
    return changed;
  }
} // namespace ddfem::scene
