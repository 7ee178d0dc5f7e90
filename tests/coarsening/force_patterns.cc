// The nodal forces of a block's force patterns
// (BlockSampler::boundary_forces()): a traction lumped to the block's
// surface, less its resultant removed over the nodes it loads.
// 1. A block of 2x2x2 voxels under a constant stress: the lumped traction
//    is already self-equilibrated and stays as it is (a face's middle node
//    takes sigma n / 4, the centre node nothing).
// 2. The same block under a linearly varying stress, whose traction has a
//    resultant force (the integral of div sigma): the forces differ from
//    those of the stress at the centre (a number pinned by the output), are
//    self-equilibrated, and the centre node, which no face loads, stays
//    free of force (the removal of the resultant over all nodes put a
//    force there).
// 3. A level-2 block whose corner voxel is void: the corner node, which
//    only that void voxel touches, stays free of force, and the forces are
//    self-equilibrated.
// 4. A level-2 block whose only solid voxel is at its corner: its faces
//    load one node, which admits no self-equilibrated force, so the
//    patterns load all faces of its child; the forces are nonzero and
//    self-equilibrated.
// 5. Two voxels that touch at the block's centre (a hinge): the forces are
//    in equilibrium as a whole, the hinge node is free of force, and each
//    voxel's forces have no moment about the hinge, which has no rotational
//    stiffness.

#include <deal.II/base/tensor.h>

#include <ddfem/coarsening/block_sampler.h>

#include <iomanip>
#include <random>

#include "../tests.h"

using namespace ddfem;
using namespace ddfem::coarsening;
using dealii::Point;
using dealii::Tensor;

namespace
{
  /// The largest component of the resultant force (@p moment false) or of
  /// the moment about the block's centre (true) of the nodal forces @p f
  /// on the nodes where @p select is true.
  double
  resultant(const BlockSampler                          &sampler,
            const dealii::Vector<double>                &f,
            const bool                                   moment,
            const std::function<bool(const Point<3> &)> &select)
  {
    const Point<3> centre(0.5, 0.5, 0.5);
    double         largest = 0;
    for (unsigned int c = 0; c < 3; ++c)
      {
        Tensor<1, 3> e;
        e[c] = 1;
        const dealii::Vector<double> u =
          sampler.interpolate([&](const Point<3> &x) {
            if (!select(x))
              return Tensor<1, 3>();
            return moment ? dealii::cross_product_3d(e, x - centre) : e;
          });
        largest = std::max(largest, std::abs(f * u));
      }
    return largest;
  }

  /// The largest component of the resultant force and moment of @p f.
  double
  resultant(const BlockSampler &sampler, const dealii::Vector<double> &f)
  {
    const auto all = [](const Point<3> &) { return true; };
    return std::max(resultant(sampler, f, false, all),
                    resultant(sampler, f, true, all));
  }

  /// The force on the node at @p p.
  Tensor<1, 3>
  node_force(const BlockSampler           &sampler,
             const dealii::Vector<double> &f,
             const Point<3>               &p)
  {
    Tensor<1, 3> force;
    for (unsigned int c = 0; c < 3; ++c)
      {
        Tensor<1, 3> e;
        e[c]     = 1;
        force[c] = f * sampler.interpolate([&](const Point<3> &x) {
          return x.distance(p) < 1e-12 ? e : Tensor<1, 3>();
        });
      }
    return force;
  }

  /// A random stress sigma0 + sum_d (2 x_d - 1) sigma_d with standard
  /// normal entries, constant if @p gradient is false.
  std::function<Tensor<2, 3>(const Point<3> &)>
  random_stress(std::mt19937 &generator, const bool gradient)
  {
    std::normal_distribution<double> normal;
    std::array<Tensor<2, 3>, 4>      sigma;
    for (auto &s : sigma)
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int j = i; j < 3; ++j)
          s[i][j] = s[j][i] = normal(generator);
    return [sigma, gradient](const Point<3> &x) {
      Tensor<2, 3> result = sigma[0];
      if (gradient)
        for (unsigned int d = 0; d < 3; ++d)
          result += (2 * x[d] - 1) * sigma[d + 1];
      return result;
    };
  }
} // namespace

int
main()
{
  material::MaterialPoint p;
  p.mu     = 1;
  p.lambda = 2;
  std::mt19937 generator(3);

  {
    // One block of voxels under a constant and a linearly varying stress.
    std::cout << "Block of 2x2x2 voxels, constant stress" << std::endl;
    std::array<std::vector<material::MaterialPoint>, 8> voxels;
    voxels.fill(std::vector<material::MaterialPoint>(8, p));
    const BlockSampler           sampler(voxels);
    const auto                   stress = random_stress(generator, false);
    const dealii::Vector<double> f      = sampler.boundary_forces(stress);
    Tensor<1, 3>                 n;
    n[2] = -1;
    testing::check_below(
      "force on the bottom face's middle node minus sigma n / 4",
      (node_force(sampler, f, Point<3>(0.5, 0.5, 0)) -
       stress(Point<3>(0.5, 0.5, 0.5)) * n / 4)
        .norm(),
      1e-14);
    testing::check_below("force on the centre node",
                         node_force(sampler, f, Point<3>(0.5, 0.5, 0.5)).norm(),
                         1e-14);

    std::cout << "Block of 2x2x2 voxels, linearly varying stress" << std::endl;
    const auto                   linear = random_stress(generator, true);
    const dealii::Vector<double> g      = sampler.boundary_forces(linear);
    // The gradient loads the nodes: the forces differ from those of the
    // stress at the centre (zero forces would pass the checks below).
    dealii::Vector<double> difference = sampler.boundary_forces(
      [&](const Point<3> &) { return linear(Point<3>(0.5, 0.5, 0.5)); });
    difference -= g;
    std::cout << "|f - f of the centre's stress| / |f|: "
              << std::setprecision(2) << difference.l2_norm() / g.l2_norm()
              << std::setprecision(6) << std::endl;
    testing::check_below("resultant force and moment",
                         resultant(sampler, g),
                         1e-14);
    testing::check_below("force on the centre node",
                         node_force(sampler, g, Point<3>(0.5, 0.5, 0.5)).norm(),
                         1e-14);
  }

  {
    std::cout << "Level-2 block with its corner voxel void" << std::endl;
    std::array<std::vector<material::MaterialPoint>, 8> children;
    children.fill(std::vector<material::MaterialPoint>(8, p));
    BlockSampler::VoidVoxels void_voxels{};
    void_voxels[0] = 1u << 0;
    const BlockSampler sampler(children, child_point_offset, void_voxels);
    const auto         stress      = random_stress(generator, true);
    const dealii::Vector<double> f = sampler.boundary_forces(stress);
    // The block without its void voxel under the same stress: the forces
    // of the voxels that are kept change little.
    const BlockSampler full(children,
                            child_point_offset,
                            BlockSampler::VoidVoxels{});
    std::cout << "|f| / |f of the full block|: " << std::setprecision(2)
              << f.l2_norm() / full.boundary_forces(stress).l2_norm()
              << std::setprecision(6) << std::endl;
    testing::check_below("resultant force and moment",
                         resultant(sampler, f),
                         1e-14);
    testing::check_below("force on the void corner's node",
                         node_force(sampler, f, Point<3>(0, 0, 0)).norm(),
                         1e-14);
  }

  {
    std::cout << "Level-2 block with one solid voxel, at its corner"
              << std::endl;
    std::array<std::vector<material::MaterialPoint>, 8> children;
    children[0].assign(8, p);
    BlockSampler::VoidVoxels void_voxels{};
    void_voxels[0] = 0xFE;
    const BlockSampler sampler(children, child_point_offset, void_voxels);
    const dealii::Vector<double> f =
      sampler.boundary_forces(random_stress(generator, true));
    testing::check_below("resultant force and moment / |f|",
                         resultant(sampler, f) / f.l2_norm(),
                         1e-14);
    std::cout << "a force on the middle node of the block's z- face, which "
                 "only void voxels' faces load: "
              << std::boolalpha
              << (node_force(sampler, f, Point<3>(0.5, 0.5, 0)).norm() >
                  1e-3 * f.l2_norm())
              << std::endl;
  }

  {
    std::cout << "Two voxels hinged at the block's centre" << std::endl;
    std::array<std::vector<material::MaterialPoint>, 8> voxels;
    voxels[0].assign(8, p);
    voxels[7].assign(8, p);
    const BlockSampler sampler(voxels);
    std::cout << "zero-energy modes: " << sampler.n_zero_energy_modes()
              << std::endl;
    const auto                   stress = random_stress(generator, true);
    const dealii::Vector<double> f      = sampler.boundary_forces(stress);
    // Against the solid block under the same stress: two of its eight
    // voxels carry a share of its surface forces.
    std::array<std::vector<material::MaterialPoint>, 8> solid;
    solid.fill(std::vector<material::MaterialPoint>(8, p));
    std::cout << "|f| / |f of the solid block|: " << std::setprecision(2)
              << f.l2_norm() /
                   BlockSampler(solid).boundary_forces(stress).l2_norm()
              << std::setprecision(6) << std::endl;
    testing::check_below("resultant force and moment",
                         resultant(sampler, f),
                         1e-14);
    testing::check_below("force on the hinge node",
                         node_force(sampler, f, Point<3>(0.5, 0.5, 0.5)).norm(),
                         1e-14);
    for (const unsigned int k : {0u, 7u})
      {
        // The voxel's nodes: those in its octant of the block.
        const auto in_voxel = [k](const Point<3> &x) {
          for (unsigned int d = 0; d < 3; ++d)
            if (k == 0 ? x[d] > 0.5 : x[d] < 0.5)
              return false;
          return true;
        };
        testing::check_below("moment of voxel " + std::to_string(k) +
                               "'s forces about the hinge",
                             resultant(sampler, f, true, in_voxel),
                             1e-14);
      }
  }
}
