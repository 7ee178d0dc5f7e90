#ifndef ddfem_scene_voxel_grid_h
#define ddfem_scene_voxel_grid_h

#include <deal.II/base/point.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ddfem::scene
{
  using namespace dealii;

  /**
   * Material identifier of a voxel: an index into the Palette, where 0 is
   * void (no material, no degrees of freedom).
   */
  using MaterialId = std::uint8_t;

  /// The material id that marks a void voxel.
  constexpr MaterialId void_id = 0;

  /**
   * A structured grid of cubic voxels with one material id each.
   *
   * Voxel (i,j,k) occupies [origin + h*(i,j,k), origin + h*(i+1,j+1,k+1)],
   * with the origin at (0,0,0). Voxels are stored lexicographically with i
   * running fastest. Vertex (i,j,k), 0 <= i <= nx, is the corner at
   * origin + h*(i,j,k).
   */
  class VoxelGrid
  {
  public:
    /// An empty (0x0x0) grid.
    VoxelGrid() = default;

    /**
     * A grid of @p n[0] x @p n[1] x @p n[2] voxels of edge length @p h
     * (meters), all set to @p fill.
     */
    VoxelGrid(const std::array<unsigned int, 3> &n,
              const double                       h,
              const MaterialId                   fill = void_id);

    /// Number of voxels along each axis.
    const std::array<unsigned int, 3> &
    size() const
    {
      return n;
    }

    /// Edge length of a voxel, in meters.
    double
    voxel_size() const
    {
      return h;
    }

    /// Total number of voxels (solid and void).
    std::size_t
    n_voxels() const
    {
      return ids.size();
    }

    /// Number of voxels whose id is not void.
    std::size_t
    n_solid_voxels() const;

    /// "nx x ny x nz voxels of h m, N solid", for the run logs.
    std::string
    describe() const;

    /// Linear index of voxel (i,j,k).
    std::size_t
    index(const unsigned int i,
          const unsigned int j,
          const unsigned int k) const
    {
      return i + static_cast<std::size_t>(n[0]) *
                   (j + static_cast<std::size_t>(n[1]) * k);
    }

    /// Voxel coordinates (i,j,k) of the linear index @p v.
    std::array<unsigned int, 3>
    coordinates(const std::size_t v) const;

    /// "voxel (i, j, k)" for the linear index @p v, for error messages.
    std::string
    voxel_name(const std::size_t v) const;

    /// Material id of voxel (i,j,k).
    MaterialId
    operator()(const unsigned int i,
               const unsigned int j,
               const unsigned int k) const
    {
      return ids[index(i, j, k)];
    }

    /// Writable material id of voxel (i,j,k).
    MaterialId &
    operator()(const unsigned int i, const unsigned int j, const unsigned int k)
    {
      return ids[index(i, j, k)];
    }

    /// Material id of the voxel with linear index @p v.
    MaterialId
    operator[](const std::size_t v) const
    {
      return ids[v];
    }

    /// Writable material id of the voxel with linear index @p v.
    MaterialId &
    operator[](const std::size_t v)
    {
      return ids[v];
    }

    /// Center of voxel (i,j,k), in meters.
    Point<3>
    center(const unsigned int i,
           const unsigned int j,
           const unsigned int k) const
    {
      return Point<3>((i + 0.5) * h, (j + 0.5) * h, (k + 0.5) * h);
    }

    /// The far corner of the grid's bounding box; the near corner is 0.
    Point<3>
    extent() const
    {
      return Point<3>(n[0] * h, n[1] * h, n[2] * h);
    }

    /// All material ids, lexicographic, i fastest.
    const std::vector<MaterialId> &
    data() const
    {
      return ids;
    }

  private:
    std::array<unsigned int, 3> n = {{0, 0, 0}};
    double                      h = 0;
    std::vector<MaterialId>     ids;
  };
} // namespace ddfem::scene

#endif
