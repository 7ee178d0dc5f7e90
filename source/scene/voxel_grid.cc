#include <deal.II/base/exceptions.h>

#include <ddfem/scene/voxel_grid.h>

#include <algorithm>
#include <sstream>

namespace ddfem::scene
{
  VoxelGrid::VoxelGrid(const std::array<unsigned int, 3> &n,
                       const double                       h,
                       const MaterialId                   fill)
    : n(n)
    , h(h)
    , ids(static_cast<std::size_t>(n[0]) * n[1] * n[2], fill)
  {
    AssertThrow(h > 0,
                ExcMessage("VoxelGrid: the voxel size must be positive."));
  }



  std::size_t
  VoxelGrid::n_solid_voxels() const
  {
    return ids.size() - std::count(ids.begin(), ids.end(), void_id);
  }



  std::string
  VoxelGrid::describe() const
  {
    std::ostringstream s;
    s << n[0] << " x " << n[1] << " x " << n[2] << " voxels of " << h << " m, "
      << n_solid_voxels() << " solid";
    return s.str();
  }



  std::array<unsigned int, 3>
  VoxelGrid::coordinates(const std::size_t v) const
  {
    AssertIndexRange(v, ids.size());
    return {{static_cast<unsigned int>(v % n[0]),
             static_cast<unsigned int>(v / n[0] % n[1]),
             static_cast<unsigned int>(v / n[0] / n[1])}};
  }



  std::string
  VoxelGrid::voxel_name(const std::size_t v) const
  {
    const auto ijk = coordinates(v);
    return "voxel (" + std::to_string(ijk[0]) + ", " + std::to_string(ijk[1]) +
           ", " + std::to_string(ijk[2]) + ")";
  }
} // namespace ddfem::scene
