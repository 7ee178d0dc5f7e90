#ifndef ddfem_tests_stability_layered_cube_h
#define ddfem_tests_stability_layered_cube_h

#include <string>

namespace ddfem::testing
{
  /**
   * Parameter text of a cube of @p n voxels of 0.01 m per side in layers of
   * materials 1 and 3 one voxel thick, clamped on its floor z- and squeezed
   * by its lid z+ to @p compression of its height in 10 load steps.
   */
  inline std::string
  compressed_cube(const unsigned int n, const double compression)
  {
    const std::string size = std::to_string(n);
    return "subsection Geometry\n  set Grid size = " + size + ", " + size +
           ", " + size +
           "\nend\n"
           "subsection Layout\n  set Type = layers\n"
           "  subsection Layers\n    set Axis = z\n    set Thickness = 0.01\n"
           "    set Materials = 1, 3\n  end\nend\n"
           "subsection Boundary conditions\n"
           "  subsection Condition 1\n    set Type = fixed\n"
           "    set Region = z-\n  end\n"
           "  subsection Condition 2\n    set Type = displacement\n"
           "    set Region = z+\n    set Value = 0; 0; -" +
           std::to_string(0.01 * n * compression) +
           "\n  end\nend\n"
           "subsection Nonlinear solver\n  set Load steps = 10\nend\n";
  }
} // namespace ddfem::testing

#endif
