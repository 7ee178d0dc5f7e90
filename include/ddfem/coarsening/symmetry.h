#ifndef ddfem_coarsening_symmetry_h
#define ddfem_coarsening_symmetry_h

#include <deal.II/base/tensor.h>

#include <ddfem/scene/voxel_grid.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace ddfem::coarsening
{
  using namespace dealii;

  /**
   * The material ids of the eight children of a 2x2x2 block, in
   * lexicographic order: child k = i + 2 j + 4 k occupies octant (i, j, k).
   */
  using Combination = std::array<std::uint8_t, 8>;

  /// Whether every child of @p c is void (such a block has no element).
  inline bool
  all_void(const Combination &c)
  {
    return std::all_of(c.begin(), c.end(), [](const std::uint8_t id) {
      return id == scene::void_id;
    });
  }

  /**
   * The 48 symmetries of the cube (rotations and reflections), acting on a
   * 2x2x2 block about its center. Symmetry g maps the child in octant k to
   * octant permutation(g)[k] and a direction v to matrix(g) v. Energies of
   * isotropic materials and of the anisotropic spring are invariant under
   * all 48, so a block's metamaterial maps to its image's metamaterial.
   * Symmetry 0 is the identity.
   */
  class CubeSymmetries
  {
  public:
    /// Builds the group: all 3x3 signed permutation matrices.
    CubeSymmetries();

    /// Number of symmetries (48).
    static constexpr unsigned int size = 48;

    /// The orthogonal matrix of symmetry @p g.
    const Tensor<2, 3> &
    matrix(const unsigned int g) const
    {
      return matrices[g];
    }

    /// Where symmetry @p g moves the child in octant @p child.
    unsigned int
    image(const unsigned int g, const unsigned int child) const
    {
      return permutations[g][child];
    }

    /// The index of the inverse of symmetry @p g.
    unsigned int
    inverse(const unsigned int g) const
    {
      return inverses[g];
    }

    /// The image of a combination: result[image(g, k)] = c[k].
    Combination
    apply(const unsigned int g, const Combination &c) const;

    /**
     * The orbit representative of @p c (the lexicographically smallest
     * image, comparing child 0 first) and a symmetry g with
     * apply(g, representative) == c.
     */
    std::pair<Combination, unsigned int>
    canonical(const Combination &c) const;

    /// The symmetries that leave @p c unchanged (its stabilizer).
    std::vector<unsigned int>
    stabilizer(const Combination &c) const;

  private:
    std::array<Tensor<2, 3>, size>                matrices;
    std::array<std::array<unsigned int, 8>, size> permutations;
    std::array<unsigned int, size>                inverses;
  };

  /**
   * The combinations of a palette with @p n_materials materials, numbered
   * as base-(n_materials + 1) numbers with child 0 the least significant
   * digit; digit 0 is void. Without void, digits run over 1..n_materials
   * only and keys over (n_materials)^8 values.
   */
  class CombinationIndex
  {
  public:
    /// Sets up the numbering for @p n_materials materials, with or without
    /// void children.
    CombinationIndex(const unsigned int n_materials, const bool with_void);

    /// Number of combinations.
    std::size_t
    size() const
    {
      return n_keys;
    }

    /// The key of a combination; throws ExcInternalError unless it
    /// contains() it.
    std::size_t
    key(const Combination &c) const;

    /// The combination of a key.
    Combination
    combination(std::size_t key) const;

    /// Whether @p c uses only ids this numbering covers.
    bool
    contains(const Combination &c) const;

    /**
     * Throws ExcMessage if @p c is neither all void (a block that gets no
     * element, which a numbering without void does not count) nor
     * contains() it: a void voxel where the numbering has no void, or a
     * material id above the palette's size. A database of this numbering
     * covers no such block.
     */
    void
    check_covered(const Combination &c) const;

    /// Whether void children are part of the numbering.
    bool
    with_void() const
    {
      return void_included;
    }

  private:
    unsigned int n_mat;
    bool         void_included;
    unsigned int base;
    std::size_t  n_keys;
  };
} // namespace ddfem::coarsening

#endif
