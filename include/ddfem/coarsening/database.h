#ifndef ddfem_coarsening_database_h
#define ddfem_coarsening_database_h

#include <ddfem/coarsening/fitting.h>
#include <ddfem/coarsening/metamaterial.h>
#include <ddfem/coarsening/symmetry.h>
#include <ddfem/scene/palette.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace ddfem::coarsening
{
  class Hierarchy;

  /// Version of the database file layout; a file with another is rejected.
  constexpr int database_format_version = 5;

  /**
   * Revision of the sampling and fitting algorithms. It is part of the
   * settings fingerprint: a file whose entries an earlier revision computed
   * is rejected, never extended with entries the present code computes
   * differently. Increase it with every change that alters entries for the
   * same settings.
   */
  constexpr int sampler_revision = 9;

  /**
   * The point offset of every child fit (Entry::child_material): the
   * Gauss rule's, whatever the first level's offset. The second level
   * samples and clusters the child fits with their records at these points,
   * so its metamaterials do not depend on the point offset first-level
   * coarsening uses.
   */
  constexpr double child_point_offset = solver::gauss_point_offset;

  /**
   * One fitted metamaterial, with how it was sampled and how well it fits:
   * at the first level that of an orbit representative combination (8
   * points), at the second (Hierarchy) that of a representative 4x4x4
   * block (64 points).
   */
  struct Entry
  {
    /// The key (CombinationIndex) of the orbit representative fitted, or at
    /// the second level the representative's index.
    std::size_t key = 0;
    /// Its metamaterial (8 or 64 points).
    Metamaterial material;
    /// The fit of the same samples with FitSettings::child_regularization
    /// for the element with child_point_offset: the block as the second
    /// level samples it (8 points; empty for second-level entries).
    Metamaterial child_material;
    /// Median and largest relative energy error on held-out samples.
    double median_error = 0, max_error = 0;
    /// Range of the kept samples' largest principal stretch deviation.
    double min_strain = 0, max_strain = 0;
    /// Samples kept (fitted or held out) and dropped (failed solves, the
    /// coarse element inverts under their corner motion, or an energy that
    /// is not finite and positive).
    unsigned int n_samples = 0, n_dropped = 0;
  };

  /**
   * The first of @p entries (sorted by key) whose key is not below @p key:
   * the entry of @p key if there is one, else where it would go.
   */
  inline std::vector<Entry>::const_iterator
  find_key(const std::vector<Entry> &entries, const std::size_t key)
  {
    return std::lower_bound(entries.begin(),
                            entries.end(),
                            key,
                            [](const Entry &e, const std::size_t k) {
                              return e.key < k;
                            });
  }

  /// Whether @p entries (sorted by key) hold one of key @p key.
  inline bool
  has_key(const std::vector<Entry> &entries, const std::size_t key)
  {
    const auto e = find_key(entries, key);
    return e != entries.end() && e->key == key;
  }

  /// Sorts @p entries by key (find_key() and has_key() need it), keeping
  /// the order of entries of equal keys.
  inline void
  sort_by_key(std::vector<Entry> &entries)
  {
    std::stable_sort(entries.begin(),
                     entries.end(),
                     [](const Entry &a, const Entry &b) {
                       return a.key < b.key;
                     });
  }

  /// Which of a first-level entry's two fits of the same samples.
  enum class Fit
  {
    /// The coarse element's (Entry::material): level-1 coarsening.
    coarse,
    /// The second level's child (Entry::child_material).
    child
  };

  /// A 64-bit FNV-1a hash of a palette description, in hex.
  std::string
  palette_hash(const std::string &palette);

  /**
   * The settings a database was built with. Two builds with equal
   * settings give equal entries, so a build resumes or extends a file
   * only if its settings match.
   */
  struct DatabaseSettings
  {
    /// The palette's description, canonical (mu and lambda per material).
    std::string palette;
    /// Whether combinations may contain void children.
    bool with_void = true;
    /// Sampling settings.
    SamplingSettings sampling;
    /// Fitting settings.
    FitSettings fitting;
    /// The coarse element's point offset (solver::coarse_quadrature()).
    double point_offset = solver::gauss_point_offset;

    /// The canonical description of @p palette.
    static std::string
    describe(const scene::Palette &palette);
    /// One line naming every setting (what files store and compare).
    std::string
    fingerprint() const;
  };

  /**
   * The settings in which two fingerprints (DatabaseSettings::fingerprint())
   * differ: "name: value in @p stored (in the file) / in @p current (here)"
   * for each, separated by "; ". A setting a fingerprint leaves out (one at
   * its default) is "default", a flag that is off "off". What errors about
   * a file or journal of other settings name.
   */
  std::string
  settings_difference(const std::string &stored, const std::string &current);

  /**
   * The first-level metamaterial database (paper sections 4 and 5): for a
   * palette, the fitted metamaterial of each symmetry orbit of 2x2x2
   * combinations, and a lookup table from every combination to an entry
   * and the cube symmetry that maps the entry onto it. Compression
   * (compress()) redirects every combination to its nearest
   * representative and drops the other entries.
   *
   * Stored as HDF5 (save(), load()). Loading validates the format
   * version, the palette, the dataset shapes and every value; a corrupt,
   * truncated or mismatched file is an ExcMessage naming the file.
   */
  class Database
  {
  public:
    /// An empty database for @p settings.
    Database(const DatabaseSettings &settings, const unsigned int n_materials);

    /**
     * Reads a database file, and its second level into @p level2 if given
     * (left empty if the file has none). Throws ExcMessage naming @p file and
     * what is wrong if it cannot be read, is not a ddfem database, or holds
     * inconsistent data.
     */
    static Database
    load(const std::string &file, Hierarchy *level2 = nullptr);

    /**
     * Writes the database, with the second level @p level2 if given, to
     * @p file atomically (a temporary file renamed
     * over it), so a reader never sees a partial file. Calls
     * check_not_read_only() first.
     */
    void
    save(const std::string &file, const Hierarchy *level2 = nullptr) const;

    /**
     * Throws ExcMessage naming Database/File if @p file exists but this
     * process may not write it (unlike ddfem::check_writable() for result
     * files, whose own permissions do not matter). save() replaces the file by
     * renaming its new content over it, which the directory allows whatever the
     * file's own permissions: a database made read-only to share it would lose
     * its protection, and its owner. A build calls it before it fits too.
     */
    static void
    check_not_read_only(const std::string &file);

    /// The canonical description of the palette it was built for.
    const std::string &
    palette() const
    {
      return palette_description;
    }

    /// The point offset of the coarse elements its metamaterials were
    /// fitted for (solver::coarse_quadrature()).
    double
    point_offset() const
    {
      return coarse_point_offset;
    }

    /// DatabaseSettings::fingerprint() of the build that made it.
    const std::string &
    fingerprint() const
    {
      return settings_fingerprint;
    }

    /// The combination numbering.
    const CombinationIndex &
    combinations() const
    {
      return index;
    }

    /// The symmetry group.
    const CubeSymmetries &
    symmetries() const
    {
      return group;
    }

    /// The fitted entries, sorted by key.
    const std::vector<Entry> &
    entries() const
    {
      return fitted;
    }

    /// Whether the metamaterial of @p c is available.
    bool
    contains(const Combination &c) const;

    /**
     * The metamaterial @p fit of combination @p c (its entry's, mapped by
     * the symmetry). Throws ExcMessage if @p c is not in the database.
     */
    Metamaterial
    lookup(const Combination &c, const Fit fit = Fit::coarse) const;

    /// The orbit representatives of @p combinations that have no entry yet,
    /// sorted and without repetitions (all-void blocks excluded). Throws
    /// like CombinationIndex::check_covered().
    std::vector<Combination>
    missing(const std::vector<Combination> &combinations) const;

    /// Adds the entry of an orbit representative and maps its orbit.
    void
    add(const Entry &entry);

    /// The number of representatives compress() was asked for
    /// (Database/Representatives; 0: not compressed). It picks fewer if
    /// fewer combinations have distinct features.
    unsigned int
    n_representatives() const
    {
      return representatives;
    }

    /**
     * Compression (paper section 4.4): every combination's feature is the
     * vector of log-energies of its metamaterial under @p deformations
     * (eq. 5); farthest point sampling from a seeded random start picks
     * @p k representatives (fewer if fewer combinations have distinct
     * features), each combination is redirected to its nearest
     * representative, and entries no combination uses are dropped. The
     * database must be complete. Returns the number of representatives
     * picked.
     */
    unsigned int
    compress(const unsigned int                      k,
             const CoarseElement                    &element,
             const std::vector<CornerDisplacements> &deformations);

    /**
     * The compression features (paper eq. 5) of every combination the
     * database has an entry for (all of them after a full build; those of
     * the scenes seen so far in lazy mode), but the all-void one: the
     * log-energies of its metamaterial @p fit under @p deformations.
     * @p keys receives the combinations' keys.
     */
    std::vector<std::vector<double>>
    features(const CoarseElement                    &element,
             const std::vector<CornerDisplacements> &deformations,
             std::vector<std::size_t>               &keys,
             const Fit                               fit = Fit::coarse) const;

  private:
    std::string        palette_description;
    std::string        settings_fingerprint;
    double             coarse_point_offset;
    CombinationIndex   index;
    CubeSymmetries     group;
    std::vector<Entry> fitted;
    /// Per combination key: the key of its entry (-1: none) and the
    /// symmetry that maps the entry's block onto it. Entry keys, not
    /// positions in @p fitted, so that add() need not renumber the table;
    /// the file stores positions.
    std::vector<std::int32_t> entry_key_of;
    std::vector<std::uint8_t> symmetry_of;
    unsigned int              representatives = 0;

    /// The entry whose key is @p entry_key (it must exist).
    const Entry &
    entry(const std::int32_t entry_key) const;
  };

  /// A clustering of feature vectors around representatives.
  struct Clustering
  {
    /// Indices of the representatives, in the order they were picked.
    std::vector<unsigned int> representatives;
    /// Per point, the index (into representatives) of its nearest one.
    std::vector<unsigned int> nearest;
  };

  /**
   * Picks @p k representatives of @p features by farthest point sampling
   * and assigns every point to its nearest representative (paper section
   * 4.4); a representative is its own nearest. The points @p required
   * (indices) are picked first, and sampling goes on from them; without
   * any, it starts from a point drawn with @p seed. If more than @p k
   * points are required, the @p k are sampled among those alone. Fewer
   * than @p k are picked if the points to sample from have fewer distinct
   * features (farthest_point_sampling()). Throws ExcMessage if there are no
   * @p features.
   */
  Clustering
  cluster(const std::vector<std::vector<double>> &features,
          const unsigned int                      k,
          const std::uint64_t                     seed,
          std::vector<unsigned int>               required = {});

  /**
   * Farthest point sampling: picks the points @p first, then repeatedly
   * the point farthest (Euclidean) from all picked ones, until @p k are
   * picked or every point coincides with a picked one. So no point is
   * picked twice, and fewer than @p k are picked if fewer points are
   * distinct. Returns the picked indices in order.
   */
  std::vector<unsigned int>
  farthest_point_sampling(const std::vector<std::vector<double>> &points,
                          const unsigned int                      k,
                          const std::vector<unsigned int>        &first);

  /**
   * The common deformations of compression features: the corner motions
   * of a homogeneous block under @p n of the sampler's force patterns
   * (seeded with @p seed) with linearized strain @p strain.
   */
  std::vector<CornerDisplacements>
  feature_deformations(const unsigned int  n,
                       const double        strain,
                       const std::uint64_t seed);

  /**
   * The feature deformations of every compression: 32 patterns at strain
   * 0.1, of level 1 and of the second level's classes (@p stage 0) and of
   * its pairing stages (@p stage 0, 1, 2), each stage seeded on its own.
   * Files built with other ones would compress differently.
   */
  inline std::vector<CornerDisplacements>
  compression_deformations(const unsigned int stage = 0)
  {
    return feature_deformations(32, 0.1, 4711 + stage);
  }

  /**
   * An append-only journal of finished entries next to a database file
   * (its name plus ".journal"): each record carries a checksum, so a
   * build killed at any moment resumes with every entry that was
   * completely written.
   */
  class Journal
  {
  public:
    /**
     * Opens the journal of @p database_file for appending; a new journal
     * starts with @p fingerprint (DatabaseSettings::fingerprint()). An
     * existing one is cut after its last complete record (as read() with
     * @p fingerprint, @p n_keys and @p level finds it), so that a torn
     * record left by an interrupted build does not hide the records
     * appended now. Throws ExcMessage if the journal cannot be created or
     * written, or if it was written with other settings.
     */
    Journal(const std::string &database_file,
            const std::string &fingerprint,
            std::size_t        n_keys,
            unsigned int       level);
    /// Closes the file.
    ~Journal();

    /// Not copyable: it owns the open file.
    Journal(const Journal &) = delete;
    /// Not copyable.
    Journal &
    operator=(const Journal &) = delete;

    /**
     * Appends @p entry and flushes it to the operating system. Throws
     * ExcMessage if it cannot be written whole (e.g. a full disk), after
     * cutting off what it wrote of it; a journal that failed once takes no
     * more records (they would follow a torn one, which read() stops at).
     */
    void
    append(const Entry &entry);

    /**
     * Reads the complete records of the journal of @p database_file
     * (none if it does not exist), whose entries are of level @p level (1:
     * 8 points and 8 child points; 2: 64 points). Reading stops at a torn
     * or damaged record: a bad checksum, a key not below @p n_keys or not a
     * whole number, another level's shape, a non-physical parameter, or
     * fit statistics out of order. Throws ExcMessage if the journal exists
     * but cannot be opened, or was written with settings other than
     * @p fingerprint.
     */
    static std::vector<Entry>
    read(const std::string &database_file,
         const std::string &fingerprint,
         std::size_t        n_keys,
         unsigned int       level);

    /// Deletes the journal of @p database_file.
    static void
    remove(const std::string &database_file);

    /// Whether @p database_file has a journal (a build of it was killed
    /// before its save).
    static bool
    exists(const std::string &database_file);

    /// The journal of @p database_file: its name plus ".journal".
    static std::string
    file_name(const std::string &database_file);

  private:
    /// The journal's file name.
    std::string name;
    /// The level of its entries (1 or 2), which fixes their shape.
    unsigned int level;
    /// The journal, open for appending; nullptr after a failed append.
    std::FILE *file;
    /// The journal's size up to its last complete record.
    std::uintmax_t valid_end;
  };

  /**
   * The name whose Journal holds the second level's fits of the database
   * @p database_file: a journal of their own, since their keys index the
   * second level's tables.
   */
  std::string
  level2_journal_base(const std::string &database_file);

  /**
   * Every file a build of the database @p database_file reads or writes
   * besides its lock: the file, the temporary Database::save() writes it
   * under first, the journals of both levels and the temporaries their
   * headers are written under first.
   */
  std::vector<std::string>
  database_files(const std::string &database_file);
} // namespace ddfem::coarsening

#endif
