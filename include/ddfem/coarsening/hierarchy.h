#ifndef ddfem_coarsening_hierarchy_h
#define ddfem_coarsening_hierarchy_h

#include <deal.II/base/parameter_handler.h>

#include <ddfem/coarsening/database.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ddfem::coarsening
{
  using namespace dealii;

  /**
   * Settings of the second coarsening level (paper section 4.5). Declared
   * in the prm subsection "Level 2" (inside "Database").
   */
  struct HierarchySettings
  {
    /// Level-1 metamaterials kept as the second level's palette.
    unsigned int n_classes = 400;
    /// Representatives after the 2x1x1 and 1x2x1 stages.
    unsigned int n_intermediate = 400;
    /// Second-level metamaterials fitted (after the 1x1x2 stage).
    unsigned int n_representatives = 400;
    /// Weight of the regularization of second-level fits toward the
    /// children's records (replaces Fitting/Regularization at level 2).
    double regularization = 1;
    /// The point offset of the second level's elements
    /// (solver::coarse_quadrature(2, point_offset)), which its
    /// metamaterials are fitted for: "Discretization/Level-2 point
    /// offset", set by DatabaseBuilder, not by parse_parameters().
    double point_offset = solver::default_level2_point_offset;
    /// How the second level's blocks are sampled: 2 since the sampler
    /// follows the voxels of partly void children (BlockSampler::
    /// VoidVoxels). Version 1 read a corner over a void voxel from its
    /// node, loaded the children's whole faces and fitted blocks with
    /// such children far too soft; files of that version name none, and a
    /// level-2 build drops their fits (fits_like()) and says so.
    unsigned int sampler_version = 2;

    /// Declares the subsection "Level 2".
    static void
    declare_parameters(ParameterHandler &prm);
    /// Reads the subsection "Level 2".
    void
    parse_parameters(ParameterHandler &prm);
    /// One line naming every setting.
    std::string
    fingerprint() const;
    /// Whether a level-2 fit made with @p other is one with these
    /// settings: the same regularization, point offset and sampler
    /// version. The budgets
    /// only choose which compositions are fitted.
    bool
    fits_like(const HierarchySettings &other) const;
  };

  /**
   * A 4x4x4 block of voxels as the level-1 keys of its eight 2x2x2
   * sub-blocks (child order; -1 for an all-void sub-block).
   */
  using BlockKeys = std::array<std::int64_t, 8>;

  /**
   * The second coarsening level (paper section 4.5): a 4x4x4 block of
   * voxels is a 2x2x2 block of level-1 elements, each modelled by its
   * entry's child fit (Fit::child). These level-1
   * metamaterials are clustered into n_classes classes (the second
   * level's palette); pairs of classes along x are clustered into
   * n_intermediate representatives, pairs of those along y likewise, and
   * pairs of those along z into the n_representatives metamaterials that
   * are fitted. Only those are sampled and fitted: each stage stores just
   * the lookup table to the next. Features are the log-energies of the
   * composite blocks (sums of their level-1 elements' energies, paper
   * eq. 5) under common deformations.
   *
   * Blocks a scene needs are required: every stage picks their parts
   * first, so, as long as they fit into the budgets, each is the
   * representative of itself and is fitted as it is, not as the nearest
   * of other compositions. Sampling then goes on over all compositions.
   *
   * A second-level metamaterial has 64 points (CoarseElement(2)); point q
   * starts from, and is regularized toward, the record of its child's
   * sub-point, whose direction it keeps.
   */
  class Hierarchy
  {
  public:
    /// The settings it was built with.
    HierarchySettings settings;

    /**
     * Builds the classes and the three stages' lookup tables from the
     * level-1 database @p level1 (every entry it has), picking the blocks
     * @p required first. Drops all entries.
     */
    void
    build_tables(const Database               &level1,
                 const HierarchySettings      &settings,
                 const std::vector<BlockKeys> &required = {});

    /// Whether the tables exist.
    bool
    empty() const
    {
      return class_key.empty();
    }

    /// Number of second-level metamaterials.
    unsigned int
    n_representatives() const
    {
      return pairs[2].size() / 2;
    }

    /// The blocks the tables were built to represent, sorted.
    const std::vector<BlockKeys> &
    required_blocks() const
    {
      return required;
    }

    /// The keys of a 4x4x4 block given as its eight 2x2x2 sub-blocks.
    /// Throws unless the block is check_representable().
    static BlockKeys
    keys(const Database &level1, const std::array<Combination, 8> &blocks);

    /**
     * The level-1 blocks (one combination per child, child 0 first; all
     * void for a void child) whose metamaterials make representative
     * @p r.
     */
    std::array<Combination, 8>
    composition(const Database &level1, const unsigned int r) const;

    /**
     * Whether the tables know every non-void combination of
     * @p combinations and were built with every non-void block of
     * @p blocks required, or with none (Scope = all: every block takes its
     * nearest representative): the tables are built from the level-1
     * entries present at the time, so a database extended later (lazy
     * mode) needs new tables. Throws ExcMessage if a combination holds a
     * material id level 1 does not cover (CombinationIndex::check_covered()).
     */
    bool
    covers(const Database                 &level1,
           const std::vector<Combination> &combinations,
           const std::vector<BlockKeys>   &blocks) const;

    /**
     * Keeps the entries of @p old (tables built before, possibly over
     * fewer level-1 entries) whose composition is a representative of these
     * tables, under their new index: a representative's fit depends on its
     * composition only.
     */
    void
    keep_entries(const Database &level1, const Hierarchy &old);

    /**
     * Throws ExcMessage if a sub-block of the 4x4x4 block given as its
     * eight 2x2x2 sub-blocks is not CombinationIndex::check_covered() by
     * the level-1 numbering @p level1, or if the block has void sub-blocks
     * next to solid ones while @p level1 has no void: the tables of such a
     * database have no void halves.
     */
    static void
    check_representable(const CombinationIndex           &level1,
                        const std::array<Combination, 8> &blocks);

    /**
     * The representative of a 4x4x4 block given as its eight 2x2x2
     * sub-blocks (child order), or -1 if all are void. Throws ExcMessage if
     * a sub-block is not covered() by the tables, or the block is not
     * check_representable().
     */
    int
    find(const Database                   &level1,
         const std::array<Combination, 8> &blocks) const;

    /// The fitted second-level entries (key = representative index).
    std::vector<Entry> entries;

    /**
     * The metamaterial of a 4x4x4 block (64 points). Throws ExcMessage if
     * its representative has not been fitted or the block is void.
     */
    Metamaterial
    lookup(const Database                   &level1,
           const std::array<Combination, 8> &blocks) const;

    /// Writes the tables and entries into the open HDF5 file @p file.
    void
    save(const std::int64_t file) const;

    /**
     * Reads them from @p file if it has a level-2 group (returns false
     * otherwise), over the level-1 database @p level1 read from it. Throws a
     * message naming what is wrong if they are inconsistent, also with
     * @p level1: every class key and every sub-block of a required block
     * must have a level-1 entry, and every class key must lie in its own
     * class.
     */
    bool
    load(const std::int64_t file, const Database &level1);

  private:
    /**
     * Replaces the classes of pairs of stage @p s in @p c (child order,
     * 8 >> s of them) by their classes at the next stage.
     */
    void
    pair_up(const unsigned int s, std::array<std::int32_t, 8> &c) const;

    /// The blocks picked first, sorted.
    std::vector<BlockKeys> required;
    /// Per level-1 key, its class; the number of classes picked
    /// (class_key.size()) for the all-void block and keys without a
    /// level-1 entry.
    std::vector<std::int32_t> class_of;
    /// The level-1 key representing each class.
    std::vector<std::int64_t> class_key;
    /// Per stage: (n_previous + 1)^2 table from a pair to a class of this
    /// stage (its count for void), and each class's representative pair.
    std::array<std::vector<std::int32_t>, 3> table;
    std::array<std::vector<std::int32_t>, 3> pairs;
  };
} // namespace ddfem::coarsening

#endif
