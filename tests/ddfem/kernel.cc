// The material kernel against finite differences: stress = d(energy)/dF,
// tangent = d(stress)/dF, for random deformation gradients and materials
// with and without the anisotropic spring; the tangent's major symmetry;
// a stress-free, energy-free reference state; the energy of a stretch
// against its closed form; frame invariance; the spring tangent's
// eigenvalues (indefinite under compression); det F <= 0 rejected.

#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/physics/transformations.h>

#include <ddfem/material/kernel.h>

#include <algorithm>
#include <random>

#include "../tests.h"

using namespace ddfem;
using namespace dealii;

int
main()
{
  std::mt19937                           random(42);
  std::uniform_real_distribution<double> uniform(-1, 1);
  const auto                             random_direction = [&]() {
    Tensor<1, 3> v({uniform(random), uniform(random), uniform(random)});
    return v / v.norm();
  };
  // I plus entries in [-0.3, 0.3].
  const auto random_deformation = [&]() {
    Tensor<2, 3> F = unit_symmetric_tensor<3>();
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        F[i][j] += 0.3 * uniform(random);
    return F;
  };

  double       stress_error = 0, tangent_error = 0, asymmetry = 0;
  unsigned int evaluated = 0; // trials with det F > 0.2
  for (unsigned int trial = 0; trial < 200; ++trial)
    {
      material::MaterialPoint m;
      m.mu     = std::pow(10., 5 + 2 * (uniform(random) + 1)); // 1e5 ... 1e9
      m.lambda = m.mu * (1 + 20 * (uniform(random) + 1));
      if (trial % 2)
        {
          m.anisotropy = m.mu * (uniform(random) + 1.5);
          m.direction  = random_direction();
        }
      const Tensor<2, 3> F = random_deformation();
      if (determinant(F) <= 0.2)
        continue;
      ++evaluated;

      material::KernelResult r;
      material::evaluate(F, m, material::KernelOutput::tangent, r);
      const double eps = 1e-6;
      for (unsigned int k = 0; k < 3; ++k)
        for (unsigned int L = 0; L < 3; ++L)
          {
            material::KernelResult plus, minus;
            Tensor<2, 3>           Fp = F, Fm = F;
            Fp[k][L] += eps;
            Fm[k][L] -= eps;
            material::evaluate(Fp, m, material::KernelOutput::stress, plus);
            material::evaluate(Fm, m, material::KernelOutput::stress, minus);
            const double dpsi = (plus.energy - minus.energy) / (2 * eps);
            stress_error =
              testing::worst(stress_error,
                             std::abs(dpsi - r.stress[k][L]) / r.stress.norm());
            for (unsigned int i = 0; i < 3; ++i)
              for (unsigned int J = 0; J < 3; ++J)
                {
                  const double dP =
                    (plus.stress[i][J] - minus.stress[i][J]) / (2 * eps);
                  tangent_error =
                    testing::worst(tangent_error,
                                   std::abs(dP - r.tangent[i][J][k][L]) /
                                     r.tangent.norm());
                  asymmetry = testing::worst(asymmetry,
                                             std::abs(r.tangent[i][J][k][L] -
                                                      r.tangent[k][L][i][J]) /
                                               r.tangent.norm());
                }
          }
    }
  std::cout << "deformations evaluated: " << evaluated << " of 200"
            << std::endl;
  testing::check_below("stress vs finite difference of energy, relative",
                       stress_error,
                       1e-7);
  testing::check_below("tangent vs finite difference of stress, relative",
                       tangent_error,
                       1e-7);
  testing::check_below("tangent major asymmetry, relative", asymmetry, 1e-14);

  // The reference state carries neither energy nor stress, also with the
  // spring (|F v| = 1 there).
  material::MaterialPoint m;
  m.mu         = 1e6;
  m.lambda     = 9e6;
  m.anisotropy = 5e5;
  m.direction  = Tensor<1, 3>({0, 0.6, 0.8});
  material::KernelResult r;
  material::evaluate(unit_symmetric_tensor<3>(),
                     m,
                     material::KernelOutput::tangent,
                     r);
  std::cout << "reference state: energy " << r.energy << ", |P| "
            << r.stress.norm() << std::endl;

  // Small strain: the tangent is the isotropic elasticity tensor.
  double deviation = 0;
  m.anisotropy     = 0;
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int J = 0; J < 3; ++J)
      for (unsigned int k = 0; k < 3; ++k)
        for (unsigned int L = 0; L < 3; ++L)
          {
            const double C = m.lambda * (i == J) * (k == L) +
                             m.mu * ((i == k) * (J == L) + (i == L) * (J == k));
            material::evaluate(unit_symmetric_tensor<3>(),
                               m,
                               material::KernelOutput::tangent,
                               r);
            deviation =
              testing::worst(deviation,
                             std::abs(r.tangent[i][J][k][L] - C) / m.lambda);
          }
  testing::check_below("tangent at F = I vs linear elasticity, relative",
                       deviation,
                       1e-14);

  // The Cauchy stress of a rotated stretch against the closed form of the
  // material, sigma = (mu (B - I) + lambda ln J I) / J with B = F F^T.
  {
    Tensor<2, 3> F;
    F[0][0] = 1.2, F[1][1] = 0.9, F[2][2] = 1.1;
    Tensor<2, 3> Q = unit_symmetric_tensor<3>();
    Q[0][0] = Q[1][1] = std::cos(0.7);
    Q[0][1]           = -std::sin(0.7);
    Q[1][0]           = std::sin(0.7);
    F                 = Q * F;
    m.anisotropy      = 0;
    material::evaluate(F, m, material::KernelOutput::stress, r);
    const double       J = determinant(F);
    const Tensor<2, 3> expected =
      (m.mu * (F * transpose(F) - unit_symmetric_tensor<3>()) +
       m.lambda * std::log(J) * unit_symmetric_tensor<3>()) /
      J;
    testing::check_below(
      "Cauchy stress of a rotated stretch vs closed form, "
      "relative",
      (material::cauchy_stress(r.stress, F) - expected).norm() /
        expected.norm(),
      1e-14);
  }

  // The largest principal linearized strain of F = I + G: sym(G) has the
  // eigenvalues 0.15, -0.1 and 0.03.
  {
    Tensor<2, 3> F = unit_symmetric_tensor<3>();
    F[0][0] += 0.1, F[0][1] += 0.2, F[1][1] -= 0.05, F[2][2] += 0.03;
    testing::check_below("linearized strain of I + G vs 0.15",
                         std::abs(material::linearized_strain(F) - 0.15),
                         1e-14);
  }

  // Hydrostatic Cauchy stress has no von Mises part; uniaxial has |sigma|.
  Tensor<2, 3> sigma;
  sigma[0][0] = sigma[1][1] = sigma[2][2] = -3e4;
  std::cout << "von Mises of hydrostatic stress: " << material::von_mises(sigma)
            << std::endl;
  sigma       = 0;
  sigma[1][1] = 2e5;
  std::cout << "von Mises of uniaxial 2e5 Pa: " << material::von_mises(sigma)
            << std::endl;
  // Pure shear tau has sqrt(3) tau; a uniaxial stress turned off the axes
  // (Q diag(s, 0, 0) Q^T, with shear entries) keeps |s|.
  sigma       = 0;
  sigma[0][1] = sigma[1][0] = 1e5;
  testing::check_below(
    "von Mises of pure shear 1e5 Pa vs sqrt(3) 1e5",
    std::abs(material::von_mises(sigma) - std::sqrt(3.) * 1e5) / 1e5,
    1e-14);
  {
    const Tensor<1, 3> e({0.36, 0.48, 0.8}); // a unit vector
    const Tensor<2, 3> turned = -2e5 * outer_product(e, e);
    testing::check_below("von Mises of uniaxial -2e5 Pa along (0.36, 0.48, "
                         "0.8) vs 2e5",
                         std::abs(material::von_mises(turned) - 2e5) / 2e5,
                         1e-14);
  }

  // The largest principal stretch deviation: a rotated stretch (1.2, 0.9,
  // 1) gives 0.2, a rotation 0, a compression to half 0.5, and a simple
  // shear of 0.5 gives the stretch 1/4 + sqrt(1 + 1/16) - 1.
  const double angle    = 0.7;
  Tensor<2, 3> rotation = unit_symmetric_tensor<3>();
  rotation[0][0] = rotation[1][1] = std::cos(angle);
  rotation[0][1]                  = -std::sin(angle);
  rotation[1][0]                  = std::sin(angle);
  Tensor<2, 3> stretch;
  stretch[0][0]            = 1.2;
  stretch[1][1]            = 0.9;
  stretch[2][2]            = 1;
  Tensor<2, 3> compression = unit_symmetric_tensor<3>();
  compression[2][2]        = 0.5;
  Tensor<2, 3> shear       = unit_symmetric_tensor<3>();
  shear[0][1]              = 0.5;
  const double strain_error =
    testing::worst(std::abs(material::principal_strain(rotation * stretch *
                                                       transpose(rotation)) -
                            0.2),
                   std::abs(material::principal_strain(rotation * stretch) -
                            0.2),
                   std::abs(material::principal_strain(rotation)),
                   std::abs(material::principal_strain(compression) - 0.5),
                   std::abs(material::principal_strain(shear) -
                            (0.25 + std::sqrt(1 + 1. / 16) - 1)));
  testing::check_below("principal strain error", strain_error, 1e-14);

  // The energy itself against its closed form. A stretch s along x, with
  // the spring along x (stretched by s) or along y (not stretched):
  // W = mu/2 (s^2 - 1) - mu ln s + lambda/2 (ln s)^2 + C (l - 1)^2.
  {
    material::MaterialPoint p;
    p.mu                = 2e5;
    p.lambda            = 1.8e6;
    p.anisotropy        = 7e5;
    const double s      = 1.3;
    Tensor<2, 3> F      = unit_symmetric_tensor<3>();
    F[0][0]             = s;
    double energy_error = 0;
    for (const unsigned int axis : {0u, 1u})
      {
        p.direction       = Tensor<1, 3>();
        p.direction[axis] = 1;
        material::evaluate(F, p, material::KernelOutput::energy, r);
        const double l     = (axis == 0 ? s : 1.);
        const double exact = 0.5 * p.mu * (s * s - 1) - p.mu * std::log(s) +
                             0.5 * p.lambda * std::log(s) * std::log(s) +
                             p.anisotropy * (l - 1) * (l - 1);
        energy_error =
          testing::worst(energy_error, std::abs(r.energy - exact) / exact);
      }
    testing::check_below("energy of a stretch vs its closed form, relative",
                         energy_error,
                         1e-14);
  }

  // Frame invariance: a rotation Q after the deformation changes neither
  // the energy nor the stress beyond P(Q F) = Q P(F); rotating the body
  // and the spring's direction together, psi(F Q^T; Q v) = psi(F; v).
  {
    double       objectivity = 0, material_rotation = 0;
    unsigned int rotated_trials = 0; // with det F > 0.2
    for (unsigned int trial = 0; trial < 50; ++trial)
      {
        material::MaterialPoint p;
        p.mu         = 1e6;
        p.lambda     = 5e6;
        p.anisotropy = 2e6;
        p.direction  = random_direction();
        const Tensor<2, 3> Q =
          Physics::Transformations::Rotations::rotation_matrix_3d(
            random_direction(), 3 * uniform(random));
        const Tensor<2, 3> F = random_deformation();
        if (determinant(F) <= 0.2)
          continue;
        ++rotated_trials;
        material::KernelResult plain, rotated, turned;
        material::evaluate(F, p, material::KernelOutput::stress, plain);
        material::evaluate(Q * F, p, material::KernelOutput::stress, rotated);
        objectivity =
          testing::worst(objectivity,
                         std::abs(rotated.energy - plain.energy) / plain.energy,
                         (rotated.stress - Q * plain.stress).norm() /
                           plain.stress.norm());
        material::MaterialPoint q = p;
        q.direction               = Q * p.direction;
        material::evaluate(F * transpose(Q),
                           q,
                           material::KernelOutput::energy,
                           turned);
        material_rotation =
          testing::worst(material_rotation,
                         std::abs(turned.energy - plain.energy) / plain.energy);
      }
    std::cout << "rotated deformations evaluated: " << rotated_trials
              << " of 50" << std::endl;
    testing::check_below("psi(QF) and P(QF) against psi(F) and Q P(F), "
                         "relative",
                         objectivity,
                         1e-12);
    testing::check_below("psi(F Q^T) with the direction Q v against psi(F), "
                         "relative",
                         material_rotation,
                         1e-12);
  }

  // The spring's tangent alone (mu = lambda = 0) is
  // 2C [a a^T / l^3 + (1 - 1/l) I] (x) v v^T with a = F v and l = |a|. As a
  // 9 x 9 matrix its eigenvalues are 2C (along a), 2C (1 - 1/l) twice
  // (across a) and 0 six times: a compressed spring (l < 1) makes it
  // indefinite, which is why coarse models can have indefinite tangents
  // where the fine model has none (doc/coarsening.md).
  for (const double l : {0.8, 1.25})
    {
      material::MaterialPoint p;
      p.anisotropy = 3e5;
      p.direction  = random_direction();
      const Tensor<2, 3> Q =
        Physics::Transformations::Rotations::rotation_matrix_3d(
          random_direction(), 3 * uniform(random));
      const Tensor<2, 3> F =
        Q * (unit_symmetric_tensor<3>() +
             (l - 1) * outer_product(p.direction, p.direction));
      material::evaluate(F, p, material::KernelOutput::tangent, r);
      LAPACKFullMatrix<double> A(9, 9);
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int J = 0; J < 3; ++J)
          for (unsigned int k = 0; k < 3; ++k)
            for (unsigned int L = 0; L < 3; ++L)
              A(3 * i + J, 3 * k + L) = r.tangent[i][J][k][L];
      A.compute_eigenvalues();
      const double        across = 2 * p.anisotropy * (1 - 1 / l);
      std::vector<double> computed(9),
        exact = {2 * p.anisotropy, across, across, 0, 0, 0, 0, 0, 0};
      for (unsigned int e = 0; e < 9; ++e)
        computed[e] = A.eigenvalue(e).real();
      std::sort(computed.begin(), computed.end());
      std::sort(exact.begin(), exact.end());
      double       eigenvalue_error = 0;
      unsigned int n_negative       = 0;
      for (unsigned int e = 0; e < 9; ++e)
        {
          eigenvalue_error =
            testing::worst(eigenvalue_error,
                           std::abs(computed[e] - exact[e]) / p.anisotropy);
          n_negative += (computed[e] < -1e-8 * p.anisotropy);
        }
      std::cout << "spring tangent at |F v| = " << l << ": " << n_negative
                << " negative eigenvalues" << std::endl;
      testing::check_below("  its eigenvalues vs 2C, 2C (1 - 1/l) twice, 0 "
                           "six times, relative to C",
                           eigenvalue_error,
                           1e-12);
    }

  // Inverted or degenerate states are inadmissible.
  Tensor<2, 3> inverted = unit_symmetric_tensor<3>();
  inverted[2][2]        = -0.1;
  std::cout << "det F < 0 admissible: " << std::boolalpha
            << material::evaluate(inverted,
                                  m,
                                  material::KernelOutput::energy,
                                  r)
            << std::endl;
  Tensor<2, 3> flat = unit_symmetric_tensor<3>();
  flat[2][2]        = 0;
  std::cout << "det F = 0 admissible: " << std::boolalpha
            << material::evaluate(flat, m, material::KernelOutput::energy, r)
            << std::endl;
}
