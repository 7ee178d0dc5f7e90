#ifndef ddfem_scene_palette_h
#define ddfem_scene_palette_h

#include <deal.II/base/parameter_handler.h>

#include <ddfem/material/kernel.h>
#include <ddfem/scene/voxel_grid.h>

#include <string>
#include <vector>

namespace ddfem::scene
{
  using namespace dealii;

  /**
   * One isotropic Neo-Hookean material of the palette, by its Lame
   * parameters (given directly or as E and nu).
   */
  struct PaletteMaterial
  {
    /// Shear modulus mu = E / (2 (1 + nu)) (Pa).
    double mu;
    /// Lame's first parameter lambda = E nu / ((1 + nu)(1 - 2 nu)) (Pa).
    double lambda;

    /// The kernel's per-point record for this material (no anisotropy).
    material::MaterialPoint
    material_point() const;
  };

  /**
   * The material palette of a scene: the materials voxel ids refer to. Id 0
   * is void; id m >= 1 is the palette's m-th entry (1-based). Declared in
   * the prm subsection "Materials".
   */
  class Palette
  {
  public:
    /// Declares the subsection "Materials".
    static void
    declare_parameters(ParameterHandler &prm);

    /// Reads and validates the subsection "Materials".
    void
    parse_parameters(ParameterHandler &prm);

    /**
     * Parses a palette description: materials separated by ';', each
     * "E=<Pa> nu=<ratio>" or "mu=<Pa> lambda=<Pa>". Throws ExcMessage naming
     * the offending entry and the allowed range when E <= 0, nu outside
     * (-1, 0.5), mu <= 0 or lambda <= -2/3 mu.
     */
    void
    parse(const std::string &description);

    /**
     * Throws, naming @p run (the method or run type, as "Method = fine"),
     * when a material has lambda < 0: the compressible Neo-Hookean energy
     * has no lower bound then, so every solve that uses it needs
     * lambda >= 0. (Linear and corotated elasticity, which DG solves, are
     * bounded for every lambda > -2/3 mu.)
     */
    void
    require_nonnegative_lambda(const std::string &run) const;

    /// Number of (non-void) materials.
    unsigned int
    size() const
    {
      return materials.size();
    }

    /// The material with voxel id @p id (1 <= id <= size()).
    const PaletteMaterial &
    operator[](const MaterialId id) const
    {
      return materials[id - 1];
    }

  private:
    std::vector<PaletteMaterial> materials;
  };
} // namespace ddfem::scene

#endif
