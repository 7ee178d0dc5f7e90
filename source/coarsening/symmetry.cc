#include <deal.II/base/exceptions.h>
#include <deal.II/base/symmetric_tensor.h>

#include <ddfem/coarsening/symmetry.h>

#include <algorithm>

namespace ddfem::coarsening
{
  CubeSymmetries::CubeSymmetries()
  {
    // Every permutation of the axes with every sign flip; the identity
    // comes first: axes (0,1,2) with no sign flips.
    std::array<unsigned int, 3> axes = {{0, 1, 2}};
    unsigned int                g    = 0;
    do
      for (unsigned int signs = 0; signs < 8; ++signs, ++g)
        {
          Tensor<2, 3> &R = matrices[g];
          for (unsigned int d = 0; d < 3; ++d)
            R[d][axes[d]] = (signs & (1u << d)) ? -1. : 1.;
          // Octant centers are (+-1/2, +-1/2, +-1/2) about the block center.
          for (unsigned int child = 0; child < 8; ++child)
            {
              Tensor<1, 3> x;
              for (unsigned int d = 0; d < 3; ++d)
                x[d] = (child & (1u << d)) ? 0.5 : -0.5;
              const Tensor<1, 3> y     = R * x;
              unsigned int       image = 0;
              for (unsigned int d = 0; d < 3; ++d)
                if (y[d] > 0)
                  image |= (1u << d);
              permutations[g][child] = image;
            }
        }
    while (std::next_permutation(axes.begin(), axes.end()));
    Assert(g == size, ExcInternalError());

    // Each symmetry's inverse: the one whose product with it is the
    // identity.
    for (unsigned int a = 0; a < size; ++a)
      for (unsigned int b = 0; b < size; ++b)
        if ((matrices[a] * matrices[b] - unit_symmetric_tensor<3>()).norm() <
            1e-12)
          inverses[a] = b;
  }



  Combination
  CubeSymmetries::apply(const unsigned int g, const Combination &c) const
  {
    Combination result;
    for (unsigned int k = 0; k < 8; ++k)
      result[permutations[g][k]] = c[k];
    return result;
  }



  std::pair<Combination, unsigned int>
  CubeSymmetries::canonical(const Combination &c) const
  {
    Combination  best      = c;
    unsigned int best_from = 0;
    for (unsigned int g = 1; g < size; ++g)
      {
        const Combination image = apply(g, c);
        if (image < best)
          {
            best      = image;
            best_from = g;
          }
      }
    // apply(best_from, c) == best, so c = apply(inverse(best_from), best).
    return {best, inverses[best_from]};
  }



  std::vector<unsigned int>
  CubeSymmetries::stabilizer(const Combination &c) const
  {
    std::vector<unsigned int> result;
    for (unsigned int g = 0; g < size; ++g)
      if (apply(g, c) == c)
        result.push_back(g);
    return result;
  }



  CombinationIndex::CombinationIndex(const unsigned int n_materials,
                                     const bool         with_void)
    : n_mat(n_materials)
    , void_included(with_void)
    , base(with_void ? n_materials + 1 : n_materials)
    , n_keys(1)
  {
    for (unsigned int k = 0; k < 8; ++k)
      n_keys *= base;
  }



  std::size_t
  CombinationIndex::key(const Combination &c) const
  {
    // Callers check first; a key outside the numbering would index past
    // the tables, in Release too.
    AssertThrow(contains(c), ExcInternalError());
    std::size_t key = 0;
    for (unsigned int k = 8; k-- > 0;)
      key = key * base + (void_included ? c[k] : c[k] - 1);
    return key;
  }



  Combination
  CombinationIndex::combination(std::size_t key) const
  {
    Combination c;
    for (unsigned int k = 0; k < 8; ++k, key /= base)
      c[k] = static_cast<std::uint8_t>(key % base + (void_included ? 0 : 1));
    return c;
  }



  void
  CombinationIndex::check_covered(const Combination &c) const
  {
    AssertThrow(all_void(c) || contains(c),
                ExcMessage("A block has a material id the metamaterial "
                           "database does not cover (void, with a database "
                           "built with Database/Include void = false, or "
                           "an id above the palette's size)."));
  }



  bool
  CombinationIndex::contains(const Combination &c) const
  {
    return std::all_of(c.begin(), c.end(), [this](const std::uint8_t id) {
      return id <= n_mat && (void_included || id > 0);
    });
  }
} // namespace ddfem::coarsening
