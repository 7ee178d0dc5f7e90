// Embedded samples of a 2x2x2 block (BlockSampler::sample() with
// SamplingSettings::embedded): the corners follow a homogeneous strain and
// the other nodes follow it up to a periodic fluctuation that minimizes the
// fine energy, so a sample is the block's homogenized energy.
// 1. A homogeneous block: the fluctuation vanishes and every sample's
//    energy is the element's energy of the same affine motion; with an
//    embedded fraction of 1/2, exactly half the samples are embedded. The
//    corners of a pattern's samples scale with its magnitudes: equal steps
//    (1, 3.875, 6.75, 9.625, 12.5 for strains 0.02 to 0.25) or, with
//    geometric spacing, equal ratios ((0.25 / 0.02)^(1/4) = 1.880).
// 2. A laminate (soft children at x < 1/2, stiff ones at x > 1/2) in the
//    small-strain limit: stretching across the layers gives the harmonic
//    mean of the P-wave moduli lambda + 2 mu, shearing across them the
//    harmonic mean of mu (the exact homogenized moduli of a laminate). The
//    affine motion without fluctuation gives the arithmetic means.
// 3. A mixed block: no sample exceeds the energy of the naive element
//    (each child's material, no fluctuation) under the same corners.
// 4. Blocks with a void child, as the builder samples them: one of a
//    single material keeps the force patterns of a free block; a mixed one
//    whose solid children are joined through faces is embedded, and no
//    sample exceeds the naive element's energy (with no energy at its void
//    child's point). Mixed children joined only at an edge or a corner,
//    and level-2 blocks with a void voxel, keep the force patterns.
//    A level-2 block whose eight children are alike is mixed and keeps its
//    embedded samples, although its fluctuation vanishes as a homogeneous
//    block's does: they are the level-2 element's energy with the
//    children's points (doc/coarsening.md says why force patterns are not
//    used there either). So is a level-1 checkerboard block, whose
//    embedded samples are the naive element's energy.
// 5. The relaxation converges at small strains and high contrast, where the
//    energy decrease of the last Newton steps is at round-off (cases that
//    failed before the relaxation took such steps by the residual).
// 6. The stretch test of an embedded block: a stiff column along x among
//    soft children puts the springs of the column's points along x and
//    those of the soft points across it; the free-block stretch test does
//    not. A block whose embedded fraction rounds to no pattern is sampled
//    and stretched as a free block.

#include <ddfem/coarsening/block_sampler.h>

#include <iomanip>
#include <sstream>

#include "../tests.h"

using namespace ddfem;
using namespace ddfem::coarsening;

namespace
{
  material::MaterialPoint
  point(const double E, const double nu)
  {
    material::MaterialPoint p;
    p.mu     = E / (2 * (1 + nu));
    p.lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    return p;
  }

  /// The naive metamaterial of @p children (void children: all zero).
  Metamaterial
  naive(const std::array<std::vector<material::MaterialPoint>, 8> &children)
  {
    Metamaterial m;
    for (const auto &child : children)
      m.points.push_back(child.empty() ? material::MaterialPoint() : child[0]);
    return m;
  }

  /// The energy of the block under u = H (x - centre) after relaxing the
  /// periodic fluctuation, and the fluctuation's size.
  double
  relaxed_energy(const BlockSampler &sampler,
                 const Tensor<2, 3> &H,
                 double             &fluctuation)
  {
    const Vector<double> u_base = sampler.homogeneous_strain(H);
    Vector<double>       w(sampler.n_fluctuation_dofs());
    AssertThrow(sampler.relax(u_base, w), ExcMessage("relax failed"));
    fluctuation = w.linfty_norm();
    double energy;
    sampler.energy(sampler.add_fluctuation(u_base, w), energy);
    return energy;
  }

  /// The largest relative difference of the embedded samples of the block
  /// of @p children to the energy of @p element with the metamaterial
  /// @p m under the same corners.
  double
  largest_difference(
    const std::array<std::vector<material::MaterialPoint>, 8> &children,
    const SamplingSettings                                    &sampling,
    const CoarseElement                                       &element,
    const Metamaterial                                        &m)
  {
    unsigned int dropped;
    double       largest = 0;
    const auto   samples = BlockSampler(children).sample(sampling, 3, dropped);
    std::cout << "samples: " << samples.size() << ", dropped: " << dropped
              << std::endl;
    for (const Sample &s : samples)
      {
        double e;
        element.energy(s.corners, m, e);
        largest = testing::worst(largest, std::abs(e - s.energy) / s.energy);
      }
    return largest;
  }

  /// The energy of the block under u = H (x - centre), no fluctuation.
  double
  affine_energy(const BlockSampler &sampler, const Tensor<2, 3> &H)
  {
    double energy;
    AssertThrow(sampler.energy(sampler.homogeneous_strain(H), energy),
                ExcMessage("inadmissible affine motion"));
    return energy;
  }
} // namespace

int
main()
{
  const CoarseElement element(1);
  SamplingSettings    sampling;
  sampling.n_directions = 20;
  sampling.embedded     = 1;

  {
    std::cout << "Homogeneous block, E = 1e6, nu = 0.45" << std::endl;
    std::array<std::vector<material::MaterialPoint>, 8> children;
    children.fill(std::vector<material::MaterialPoint>(8, point(1e6, 0.45)));
    const BlockSampler sampler(children);
    unsigned int       dropped;
    const auto         samples = sampler.sample(sampling, 3, dropped);
    std::cout << "samples: " << samples.size() << ", dropped: " << dropped
              << ", fluctuation unknowns: " << sampler.n_fluctuation_dofs()
              << std::endl;
    double largest = 0;
    for (const Sample &s : samples)
      {
        double e;
        element.energy(s.corners, naive(children), e);
        largest = testing::worst(largest, std::abs(e - s.energy) / s.energy);
      }
    testing::check_below("largest relative energy difference to the affine "
                         "element",
                         largest,
                         1e-10);
    SamplingSettings half = sampling;
    half.embedded         = 0.5;
    unsigned int affine   = 0;
    for (const Sample &s : sampler.sample(half, 3, dropped))
      {
        double e;
        element.energy(s.corners, naive(children), e);
        affine += (std::abs(e - s.energy) < 1e-10 * s.energy);
      }
    std::cout << "embedded fraction 0.5: samples equal to the affine element's "
                 "energy: "
              << affine << std::endl;
    // An embedded fraction of 0.2: the fit's held-out split (every fifth
    // label, FittingSettings::held_out_every) leaves embedded samples to
    // fit. Labelled by their pattern's own index, the embedded patterns
    // were patterns 4, 9, 14, ..., exactly the held-out ones.
    SamplingSettings fifth       = sampling;
    fifth.embedded               = 0.2;
    unsigned int embedded_fitted = 0, embedded_held_out = 0, force_held_out = 0;
    for (const Sample &s : sampler.sample(fifth, 3, dropped))
      {
        double e;
        element.energy(s.corners, naive(children), e);
        const bool held_out = (s.pattern % 5 == 4);
        if (std::abs(e - s.energy) < 1e-10 * s.energy)
          (held_out ? embedded_held_out : embedded_fitted) += 1;
        else
          force_held_out += held_out;
      }
    std::cout << "embedded fraction 0.2, every fifth label held out: "
              << embedded_fitted << " embedded samples fitted, "
              << embedded_held_out << " held out; " << force_held_out
              << " force samples held out" << std::endl;
    Tensor<2, 3> H;
    H[0][0] = 0.1, H[0][1] = H[1][0] = 0.05, H[2][2] = -0.08;
    double fluctuation;
    relaxed_energy(sampler, H, fluctuation);
    testing::check_below("fluctuation under a homogeneous strain",
                         fluctuation,
                         1e-12);

    // The corners of a homogeneous block's embedded samples follow the
    // magnitude exactly, so their size relative to the pattern's first
    // sample is the ratio of the magnitudes' linearized strains.
    for (const bool geometric : {false, true})
      {
        SamplingSettings spaced  = sampling;
        spaced.n_directions      = 1;
        spaced.geometric_spacing = geometric;
        const auto pattern       = sampler.sample(spaced, 3, dropped);
        const auto size          = [](const CornerDisplacements &corners) {
          double sum = 0;
          for (const Tensor<1, 3> &c : corners)
            sum += c.norm_square();
          return std::sqrt(sum);
        };
        std::ostringstream ratios;
        ratios << std::setprecision(4);
        for (const Sample &s : pattern)
          ratios << ' ' << size(s.corners) / size(pattern.front().corners);
        std::cout << "magnitudes of a pattern, "
                  << (geometric ? "geometric" : "even")
                  << " spacing (strains 0.02 to 0.25):" << ratios.str()
                  << std::endl;
      }
  }

  {
    std::cout << "A level-2 block of eight alike mixed children (each a "
                 "level-1 metamaterial with E = 1e7 at its points 0, 3 and 6, "
                 "1e5 at the others)"
              << std::endl;
    std::vector<material::MaterialPoint> child;
    for (unsigned int q = 0; q < 8; ++q)
      child.push_back(point(q % 3 == 0 ? 1e7 : 1e5, 0.3));
    std::array<std::vector<material::MaterialPoint>, 8> children;
    children.fill(child);
    const CoarseElement level2(2);
    Metamaterial        copied;
    for (unsigned int q = 0; q < level2.n_points(); ++q)
      copied.points.push_back(
        children[level2.child_of_point(q)][level2.subpoint_of_point(q)]);
    testing::check_below("largest relative energy difference of its embedded "
                         "samples to the level-2 element with the children's "
                         "points",
                         largest_difference(children, sampling, level2, copied),
                         1e-10);
  }

  {
    // So does a mixed block whose every material sits symmetrically (the
    // octants' sign vectors of each material's children add up to 0): the
    // forces on the periodic classes cancel, and its embedded samples are
    // the naive element's energy. doc/coarsening.md says why such blocks
    // keep them.
    std::cout << "A level-1 checkerboard block (E = 1e7 at children 0, 3, "
                 "5 and 6, 1e5 at the others)"
              << std::endl;
    std::array<std::vector<material::MaterialPoint>, 8> children;
    for (unsigned int k = 0; k < 8; ++k)
      children[k].assign(8,
                         point(k == 0 || k == 3 || k == 5 || k == 6 ? 1e7 : 1e5,
                               0.3));
    testing::check_below(
      "largest relative energy difference of its embedded "
      "samples to the naive element",
      largest_difference(children, sampling, element, naive(children)),
      1e-10);
  }

  {
    const material::MaterialPoint soft  = point(1e5, 0.3),
                                  stiff = point(1e7, 0.3);
    std::cout << "Laminate, E = 1e5 at x < 1/2 and 1e7 at x > 1/2, nu = 0.3"
              << std::endl;
    std::array<std::vector<material::MaterialPoint>, 8> children;
    for (unsigned int k = 0; k < 8; ++k)
      children[k].assign(8, (k & 1) ? stiff : soft);
    const BlockSampler sampler(children);
    const double       delta    = 1e-5;
    const auto         harmonic = [](const double a, const double b) {
      return 2. / (1. / a + 1. / b);
    };
    const double M_soft  = soft.lambda + 2 * soft.mu,
                 M_stiff = stiff.lambda + 2 * stiff.mu;

    Tensor<2, 3> stretch;
    stretch[0][0] = delta;
    double       fluctuation;
    const double E_stretch = relaxed_energy(sampler, stretch, fluctuation);
    const double exact_stretch =
      0.5 * harmonic(M_soft, M_stiff) * delta * delta;
    const double affine_stretch =
      affine_energy(sampler, stretch) /
      (0.5 * 0.5 * (M_soft + M_stiff) * delta * delta);
    std::cout << "stretch across the layers: energy / harmonic mean "
              << std::setprecision(6) << E_stretch / exact_stretch
              << ", without the fluctuation / arithmetic mean "
              << affine_stretch << std::endl;
    testing::check_below("relative error of the stretch energy",
                         std::abs(E_stretch / exact_stretch - 1),
                         1e-4);
    testing::check_below("relative error of the affine stretch energy",
                         std::abs(affine_stretch - 1),
                         1e-4);

    Tensor<2, 3> shear;
    shear[1][0]          = delta; // u_y = delta x
    const double E_shear = relaxed_energy(sampler, shear, fluctuation);
    const double exact_shear =
      0.5 * harmonic(soft.mu, stiff.mu) * delta * delta;
    const double affine_shear =
      affine_energy(sampler, shear) /
      (0.5 * 0.5 * (soft.mu + stiff.mu) * delta * delta);
    std::cout << "shear across the layers: energy / harmonic mean "
              << E_shear / exact_shear
              << ", without the fluctuation / arithmetic mean " << affine_shear
              << std::endl;
    testing::check_below("relative error of the shear energy",
                         std::abs(E_shear / exact_shear - 1),
                         1e-4);
    testing::check_below("relative error of the affine shear energy",
                         std::abs(affine_shear - 1),
                         1e-4);
  }

  {
    std::cout << "Mixed block: one stiff child (E = 1e7) among soft ones "
                 "(E = 1e5)"
              << std::endl;
    std::array<std::vector<material::MaterialPoint>, 8> children;
    for (unsigned int k = 0; k < 8; ++k)
      children[k].assign(8, point(k == 5 ? 1e7 : 1e5, 0.45));
    const BlockSampler sampler(children);
    unsigned int       dropped;
    const auto         samples = sampler.sample(sampling, 5, dropped);
    unsigned int       above   = 0;
    for (const Sample &s : samples)
      {
        double e;
        element.energy(s.corners, naive(children), e);
        // Not at or below it counts too: a NaN energy is a failure.
        above += !(s.energy <= e * (1 + 1e-12));
      }
    std::cout << "samples: " << samples.size() << ", dropped: " << dropped
              << ", above the naive element's energy: " << above << std::endl;
  }

  {
    // Sampled as the database builder samples them, with the settings of
    // SamplingSettings::for_block().
    std::cout << "Blocks with a void child" << std::endl;
    SamplingSettings free_block = sampling;
    free_block.embedded         = 0;
    const auto sample_like_builder =
      [&](const std::array<std::vector<material::MaterialPoint>, 8> &children,
          const std::vector<scene::MaterialId>                      &ids) {
        const BlockSampler sampler(children);
        unsigned int       dropped_a, dropped_b;
        const auto   a = sampler.sample(sampling.for_block(ids), 9, dropped_a);
        const auto   b = sampler.sample(free_block, 9, dropped_b);
        bool         same           = a.size() == b.size();
        unsigned int above          = 0;
        const Metamaterial unfitted = naive(children);
        for (unsigned int s = 0; s < a.size(); ++s)
          {
            same = same && a[s].energy == b[s].energy;
            double e;
            element.energy(a[s].corners, unfitted, e);
            above += !(a[s].energy <= e * (1 + 1e-12));
          }
        std::cout << "samples: " << a.size() << ", dropped: " << dropped_a
                  << "; equal to the force patterns': "
                  << (same ? "yes" : "no");
        // Embedded samples only: the corners of a void child follow a
        // free block's nodes by a least-squares fit.
        if (!same)
          std::cout << ", above the naive element's energy: " << above;
        std::cout << std::endl;
      };
    std::array<std::vector<material::MaterialPoint>, 8> children;
    for (unsigned int k = 1; k < 8; ++k)
      children[k].assign(8, point(1e6, 0.45));
    std::cout << "one material: ";
    sample_like_builder(children, {0, 1, 1, 1, 1, 1, 1, 1});
    children[7].assign(8, point(1e7, 0.45));
    std::cout << "a stiff child among soft ones: ";
    sample_like_builder(children, {0, 1, 1, 1, 1, 1, 1, 2});
  }

  {
    std::cout << "Relaxation at small strains, E = 1e5, 1e6, 1e7, nu = 0.45"
              << std::endl;
    const std::array<material::MaterialPoint, 3> palette = {
      {point(1e5, 0.45), point(1e6, 0.45), point(1e7, 0.45)}};
    const auto relaxes = [&](const std::string &ids,
                             const unsigned int i,
                             const unsigned int j,
                             const double       strain) {
      std::array<std::vector<material::MaterialPoint>, 8> children;
      for (unsigned int k = 0; k < 8; ++k)
        children[k].assign(8, palette[ids[k] - '1']);
      const BlockSampler sampler(children);
      Tensor<2, 3>       H;
      H[i][j] = H[j][i]           = strain;
      const Vector<double> u_base = sampler.homogeneous_strain(H);
      Vector<double>       w(sampler.n_fluctuation_dofs());
      std::cout << ids << ", strain " << strain << " in " << i << j << ": "
                << (sampler.relax(u_base, w) ? "converged" : "failed")
                << std::endl;
    };
    relaxes("23131111", 1, 2, 1e-3);
    relaxes("31111111", 0, 0, 1e-3);
    relaxes("32111111", 0, 0, 1e-2);
    relaxes("22111111", 1, 2, 1e-2);
  }

  {
    std::cout << "Stretch test of a stiff column along x (children 6 and 7, "
                 "E = 1e7) among soft children (E = 1e5)"
              << std::endl;
    std::array<std::vector<material::MaterialPoint>, 8> children;
    for (unsigned int k = 0; k < 8; ++k)
      children[k].assign(8, point(k >= 6 ? 1e7 : 1e5, 0.45));
    const BlockSampler sampler(children);
    const auto         report = [&](const std::string      &name,
                            const SamplingSettings &settings) {
      const auto directions = sampler.anisotropy_directions(settings, element);
      bool       column_along_x = true, soft_across_x = true;
      for (unsigned int q = 0; q < 8; ++q)
        if (q >= 6)
          column_along_x &= std::abs(directions[q][0]) > 1 - 1e-6;
        else
          soft_across_x &= std::abs(directions[q][0]) < 1e-2;
      // (An eigenvector's sign is arbitrary.)
      Tensor<1, 3> v;
      for (unsigned int d = 0; d < 3; ++d)
        v[d] = std::round(100 * std::abs(directions[6][d])) / 100;
      std::cout << name << ": column's springs along x: "
                << (column_along_x ? "yes" : "no")
                << ", soft points' springs across x: "
                << (soft_across_x ? "yes" : "no")
                << "; point 6's spring along |v| = (" << v << ")" << std::endl;
    };
    report("embedded block", sampling);
    SamplingSettings free_block = sampling;
    free_block.embedded         = 0;
    report("free block", free_block);
    // A fraction too small for one of the 20 patterns to be embedded: the
    // block is sampled with force patterns only, and stretched as a free
    // block.
    SamplingSettings too_few = sampling;
    too_few.embedded         = 0.04;
    unsigned int dropped_a, dropped_b;
    const auto   a    = sampler.sample(too_few, 9, dropped_a);
    const auto   b    = sampler.sample(free_block, 9, dropped_b);
    bool         same = !a.empty() && a.size() == b.size();
    for (unsigned int s = 0; same && s < a.size(); ++s)
      same = a[s].energy == b[s].energy;
    std::cout << "embedded fraction 0.04 of 20 patterns: "
              << too_few.n_embedded() << " embedded; samples equal to the "
              << "free block's: " << (same ? "yes" : "no") << std::endl;
    report("  its stretch test", too_few);
  }

  {
    std::cout << "Embedded fraction per block (set: " << sampling.embedded
              << ")" << std::endl;
    const auto report = [&](const std::string                    &name,
                            const std::vector<scene::MaterialId> &voxels) {
      std::cout << name << ": " << sampling.for_block(voxels).embedded
                << std::endl;
    };
    report("homogeneous 2x2x2", std::vector<scene::MaterialId>(8, 2));
    report("mixed 2x2x2", {1, 1, 2, 1, 1, 1, 1, 3});
    report("checkerboard 2x2x2", {2, 1, 1, 2, 1, 2, 2, 1});
    report("mixed 2x2x2 with a void voxel", {1, 1, 2, 1, 0, 1, 1, 3});
    report("one material with a void voxel", {1, 1, 1, 1, 0, 1, 1, 1});
    report("two materials joined at an edge", {1, 0, 0, 2, 0, 0, 0, 0});
    report("two materials joined at a corner", {1, 0, 0, 0, 0, 0, 0, 2});
    report("homogeneous 4x4x4", std::vector<scene::MaterialId>(64, 3));
    // Listed child by child, as DatabaseBuilder passes them.
    const std::vector<scene::MaterialId> mixed = {1, 1, 2, 1, 1, 1, 1, 3};
    std::vector<scene::MaterialId>       alike;
    for (unsigned int k = 0; k < 8; ++k)
      alike.insert(alike.end(), mixed.begin(), mixed.end());
    report("4x4x4 of eight alike mixed 2x2x2 children", alike);
    std::vector<scene::MaterialId> voxels(64, 1);
    voxels[40] = 2;
    report("4x4x4 with one other voxel", voxels);
    voxels[63] = scene::void_id;
    report("the same with a void voxel", voxels);
  }
}
