#include <deal.II/base/utilities.h>

#include <ddfem/base/parsing.h>
#include <ddfem/scene/palette.h>

namespace ddfem::scene
{
  namespace
  {
    /// The largest |mu| and |lambda| of a palette material (Pa).
    constexpr double max_modulus = 1e20;
    /// The smallest mu of a palette material (Pa): far smaller moduli are
    /// subnormal or make displacements overflow.
    constexpr double min_modulus = 1e-20;
  } // namespace



  material::MaterialPoint
  PaletteMaterial::material_point() const
  {
    material::MaterialPoint point;
    point.mu     = mu;
    point.lambda = lambda;
    return point;
  }



  void
  Palette::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Materials");
    prm.declare_entry(
      "Palette",
      "E=1e5 nu=0.45; E=1e6 nu=0.45; E=1e7 nu=0.45",
      Patterns::Anything(),
      "The compressible Neo-Hookean materials voxels refer to, separated by "
      "';'. Voxel id 0 is void, id m >= 1 is the m-th material here. Each "
      "material is either 'E=<Young's modulus in Pa> nu=<Poisson ratio>' "
      "with E > 0 and -1 < nu < 0.5, or 'mu=<Pa> lambda=<Pa>' with mu > 0 "
      "and lambda > -2/3 mu; mu at least 1e-20 Pa, mu and |lambda| at most "
      "1e20 Pa. Every run but Method = dg (Run type = compare and database "
      "too) needs nu >= 0 (lambda >= 0) of every material listed: with "
      "lambda < 0 the Neo-Hookean energy has no lower bound under "
      "compression. The default is the paper's palette.");
    prm.leave_subsection();
  }



  void
  Palette::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Materials");
    parse(prm.get("Palette"));
    prm.leave_subsection();
  }



  void
  Palette::parse(const std::string &description)
  {
    std::vector<PaletteMaterial> result;
    for (const std::string &entry :
         split_list(description, ';', "Materials/Palette"))
      {
        const std::string where = "Materials/Palette, material " +
                                  std::to_string(result.size() + 1) + " (\"" +
                                  entry + "\")";
        std::map<std::string, double> values;
        for (const std::string &pair : split_words(entry))
          {
            const auto tokens = split_list(pair,
                                           '=',
                                           "Materials/Palette, material " +
                                             std::to_string(result.size() + 1));
            AssertThrow(tokens.size() == 2,
                        ExcMessage(where +
                                   ": expected 'name=value' pairs, got \"" +
                                   pair + "\"."));
            AssertThrow(values.count(tokens[0]) == 0,
                        ExcMessage(where + ": \"" + tokens[0] +
                                   "\" is given twice."));
            values[tokens[0]] = parse_number(tokens[1], where);
          }

        PaletteMaterial m;
        if (values.size() == 2 && values.count("E") && values.count("nu"))
          {
            const double E = values["E"], nu = values["nu"];
            AssertThrow(E > 0,
                        ExcMessage(where + ": Young's modulus E must be > 0."));
            AssertThrow(nu > -1 && nu < 0.5,
                        ExcMessage(
                          where + ": Poisson ratio nu must lie in (-1, 0.5)."));
            m.mu     = E / (2 * (1 + nu));
            m.lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
          }
        else if (values.size() == 2 && values.count("mu") &&
                 values.count("lambda"))
          {
            m.mu     = values["mu"];
            m.lambda = values["lambda"];
            AssertThrow(m.mu > 0, ExcMessage(where + ": mu must be > 0."));
            AssertThrow(m.lambda > -2. / 3. * m.mu,
                        ExcMessage(where + ": lambda must be > -2/3 mu."));
          }
        else
          AssertThrow(
            false,
            ExcMessage(
              where + ": give exactly 'E=... nu=...' or 'mu=... lambda=...'."));
        // Energies and residuals sum moduli times strains over the cells:
        // far larger moduli overflow them to infinity.
        AssertThrow(m.mu <= max_modulus && std::abs(m.lambda) <= max_modulus,
                    ExcMessage(
                      where + ": mu = " + format_number(m.mu) +
                      " Pa and lambda = " + format_number(m.lambda) +
                      " Pa, but |mu| and |lambda| must be at most 1e20 Pa" +
                      (values.count("nu") ?
                         " (they grow with E, and without bound as nu "
                         "approaches -1 or 0.5)." :
                         ".")));
        AssertThrow(m.mu >= min_modulus,
                    ExcMessage(where + ": mu = " + format_number(m.mu) +
                               " Pa, but it must be at least 1e-20 Pa."));
        result.push_back(m);
      }
    AssertThrow(!result.empty() && result.size() < 255,
                ExcMessage("Materials/Palette must list between 1 and 254 "
                           "materials, found " +
                           std::to_string(result.size()) + "."));
    materials = std::move(result);
  }



  void
  Palette::require_nonnegative_lambda(const std::string &run) const
  {
    for (std::size_t m = 0; m < materials.size(); ++m)
      AssertThrow(
        materials[m].lambda >= 0,
        ExcMessage(
          "Materials/Palette: material " + std::to_string(m + 1) +
          " has lambda = " + format_number(materials[m].lambda) +
          " Pa < 0 (nu < 0). " + run +
          " needs nu >= 0 (lambda >= 0): the compressible Neo-Hookean "
          "energy mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2 has no lower "
          "bound when lambda < 0 (it falls without limit as J -> 0), so a "
          "solve fails once a compression passes the largest pressure the "
          "material bears. Method = dg (linear or corotated elasticity) "
          "takes -1 < nu < 0.5."));
  }
} // namespace ddfem::scene
