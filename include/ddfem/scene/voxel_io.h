#ifndef ddfem_scene_voxel_io_h
#define ddfem_scene_voxel_io_h

#include <deal.II/base/point.h>

#include <ddfem/scene/voxel_grid.h>

#include <array>
#include <string>
#include <vector>

namespace ddfem::scene
{
  using namespace dealii;

  /**
   * Reads material ids from a voxel file into @p grid.
   *
   * The file is plain text; a '#' starts a comment that runs to the end of
   * its line. The first non-comment line holds three integers "nx ny nz" which
   * must equal the size of @p grid. Then follow nx*ny*nz integer material ids
   * in lexicographic order (i fastest, then j, then k), separated by any white
   * space. Every id must be less than @p n_ids, the number of ids: void
   * (0) and the palette's materials (1 to @p n_ids - 1).
   *
   * Throws ExcMessage naming the file and the problem (unreadable file,
   * size mismatch, too few or too many ids, id out of range, non-integer
   * token) without modifying @p grid.
   */
  void
  read_voxel_file(const std::string &filename,
                  const unsigned int n_ids,
                  VoxelGrid         &grid);

  /**
   * A closed triangulated surface, in meters.
   */
  struct TriangleMesh
  {
    /// Vertex positions.
    std::vector<Point<3>> vertices;
    /// Vertex indices of each triangle.
    std::vector<std::array<unsigned int, 3>> triangles;
  };

  /**
   * Reads a triangle surface from an STL file (ASCII or binary) or a
   * Wavefront OBJ file (vertices "v x y z" and faces "f a b c ...",
   * polygons fan-triangulated, "a/b/c" index forms and negative indices
   * accepted). The format is chosen by the file extension (.stl, .obj, case
   * insensitive). Throws ExcMessage naming the file on any error
   * (unreadable, unknown extension, malformed line, index out of range, no
   * triangles).
   */
  TriangleMesh
  read_surface_mesh(const std::string &filename);

  /**
   * Uniformly scales and translates @p mesh so that its bounding box is
   * centered in the box [lower, upper] and fills it along the tightest axis.
   */
  void
  fit_to_box(TriangleMesh &mesh, const Point<3> &lower, const Point<3> &upper);

  /**
   * Sets every voxel of @p grid whose center lies inside the closed
   * surface @p mesh to @p material. Inside is decided along a ray parallel
   * to the z axis for each (i,j) column, robust against rays that graze
   * edges and vertices (the ray and the voxel centers on it are perturbed
   * deterministically by tiny irrational offsets, so a face through a row
   * of centers is decided alike in every column): by the winding number if the
   * mesh's triangles can be oriented consistently, so that overlapping closed
   * bodies make their union, and by parity otherwise (a shell that cannot be
   * oriented, or half of whose triangles face each way). Each shell is oriented
   * the way most of its triangles are: a few reversed triangles are repaired,
   * and a cavity's inward-facing shell stays a cavity (one that faces outward,
   * as its body does, fills it). Voxels outside are left unchanged.
   */
  void
  voxelize(const TriangleMesh &mesh,
           const MaterialId    material,
           VoxelGrid          &grid);
} // namespace ddfem::scene

#endif
