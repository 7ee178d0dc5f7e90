#ifndef ddfem_coarsening_builder_h
#define ddfem_coarsening_builder_h

#include <deal.II/base/parameter_handler.h>

#include <ddfem/base/files.h>
#include <ddfem/coarsening/database.h>
#include <ddfem/coarsening/hierarchy.h>
#include <ddfem/scene/palette.h>
#include <ddfem/scene/voxel_grid.h>

#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace ddfem::coarsening
{
  using namespace dealii;

  /**
   * Runs fit(i) for every i < @p n on @p n_threads threads (0: deal.II's
   * MultithreadInfo::n_threads()) and hands each result to store() under a
   * lock, drawing a progress bar with an ETA on @p out if @p show_progress.
   *
   * The first exception thrown by fit() or store() in any thread stops the
   * others from starting new work; it is rethrown once all threads have
   * joined, so the entries stored before it stay stored (and journaled).
   */
  void
  fit_in_parallel(const std::size_t                              n,
                  const unsigned int                             n_threads,
                  const std::function<Entry(const std::size_t)> &fit,
                  const std::function<void(const Entry &)>      &store,
                  std::ostream                                  &out,
                  const bool                                     show_progress);

  /**
   * Builds, extends and resumes first-level metamaterial databases (the
   * offline half of DDFEM, paper section 4). Declared in the prm
   * subsection "Database" (with "Sampling", "Fitting" and "Level 2"
   * inside it); it also reads "Discretization/Coarse point offset" and
   * "Discretization/Level-2 point offset", the elements the metamaterials
   * are fitted for.
   *
   * Every combination is fitted from its own seeded generator, so entries
   * do not depend on the number of threads or on the order they finish
   * in. Finished entries go to a journal at once; a killed build resumes
   * from the file plus its journal and loses none of them.
   */
  class DatabaseBuilder
  {
  public:
    /// Which combinations a run fits.
    enum class Scope
    {
      /// Every combination of the palette (one fit per symmetry orbit).
      all,
      /// Only the combinations of the scene's 2x2x2 blocks (lazy mode).
      scene
    };

    /// Declares the subsection "Database" and the coarse elements'
    /// "Discretization/Coarse point offset" and "Level-2 point offset".
    static void
    declare_parameters(ParameterHandler &prm);
    /// Reads what declare_parameters() declares and validates the point
    /// offsets, which every coarse model uses; check_input() validates the
    /// rest, which only database builds and ddfem models use.
    void
    parse_parameters(ParameterHandler &prm);

    /// The point offset (solver::coarse_quadrature()) of the coarse
    /// elements of coarsening level @p level (1 or 2), which every coarse
    /// model of that level uses and its fits are made for.
    double
    point_offset(const unsigned int level) const
    {
      return level == 2 ? hierarchy.point_offset : coarse_point_offset;
    }

    /// What a run fits.
    Scope
    scope() const
    {
      return run_scope;
    }

    /// Database/File with its symbolic links followed: the file that
    /// saves replace.
    const std::string &
    file() const
    {
      return database_file;
    }

    /// The settings a build for @p palette uses.
    DatabaseSettings
    settings(const scene::Palette &palette) const;

    /**
     * Throws ExcMessage if a database for @p palette up to level @p level
     * (the highest this run fits) cannot be built with these settings (no
     * Database/File, more held-out patterns than patterns, compression of a
     * lazy build, more than 9 material ids, void included; lambda < 0; at
     * level 2, a level-2 regularization of 0) or Database/File's directory
     * cannot be made. Writes nothing.
     */
    void
    check_input(const scene::Palette &palette, const unsigned int level) const;

    /**
     * check_input() for a simulation at coarsening @p level, whose lazy
     * fits (prepare()) compress nothing: throws ExcMessage first if
     * Database/Representatives asks for compression. Writes nothing.
     */
    void
    check_simulation_input(const scene::Palette &palette,
                           const unsigned int    level) const;

    /**
     * check_input(), and throws ExcMessage if a build with these settings
     * cannot fit the blocks of @p grids (Scope = scene): a grid that
     * Database/Levels cannot coarsen, or a block that the database cannot
     * hold (void next to solid voxels without Database/Include void).
     * build() finds these too, but only after lock() has made the file's
     * directory and lock file; this writes nothing. prepare() calls it.
     */
    void
    check_scene(const scene::Palette                &palette,
                const std::vector<scene::VoxelGrid> &grids) const;

    /**
     * After check_input(), locks Database/File for this process until the
     * returned object is destroyed: a FileLock on the resolved path
     * (resolved_path()) of Database/File + ".lock", whose directory is made if
     * missing. Hold it from open() to the end of build(): two ddfem processes
     * that use the same file then take turns instead of overwriting each
     * other's entries. Waits, with a message on @p out, while another process
     * holds it. prepare() takes it itself. Throws ExcMessage naming
     * Database/File first if something other than a regular file (a directory,
     * a named pipe) is in the way of the file, its journals or their
     * temporaries.
     */
    std::unique_ptr<FileLock>
    lock(const scene::Palette &palette, std::ostream &out) const;

    /**
     * After check_input(), loads the database for @p palette from
     * Database/File, or starts an empty one if there is none, and adds what the
     * file's journal holds; the file's second level goes to @p level2 (empty
     * if it has none). Throws ExcMessage if the file was built for another
     * palette or with other settings, or fails the checks of
     * Database::load(), at either level. Reads only: call it under lock() if
     * build() follows.
     */
    Database
    open(const scene::Palette &palette,
         Hierarchy            &level2,
         std::ostream         &out) const;

    /**
     * Fits the missing orbit representatives of every combination (or, if
     * @p scene_grids is given, of their 2x2x2 blocks) into @p database, which
     * with @p level2 is what open() read (under the same lock()), in
     * parallel and journaled, compresses if asked, saves to Database/File; with
     * Levels = 2 then builds the staged level-2 tables and fits the
     * level-2 representatives (all, or those of @p scene_grids' 4x4x4
     * blocks), journaled too. Prints a report to @p out; with
     * @p show_progress a progress bar with the estimated time left, and
     * timings. The file is written only if something was added, a journal
     * is left by a build killed before its save (its entries are saved;
     * open() recovers the level-1 ones), the build compressed or renewed
     * the level-2 tables, or the file does not exist yet; the journals are
     * removed once it is. A level-1 build keeps the file's level 2 (unless
     * it compresses). On return @p level2 holds the level 2 the file has
     * (with Levels = 2, the tables and entries built). Level-2 tables are
     * built anew if they
     * do not know a combination the build covers (built before lazy builds
     * extended level 1) or were not built with @p scene_grids' 4x4x4 blocks
     * required, or with other Database/Level 2 settings; the new tables
     * require the blocks and the earlier ones, and keep the fits of
     * compositions they still represent if those were made with the same
     * level-2 regularization, point offset and sampler version
     * (HierarchySettings::fits_like()); otherwise the dropped fits are
     * reported. With Levels = 2,
     * a grid of @p scene_grids whose size is not a multiple of 4 is an
     * error before anything is fitted.
     */
    void
    build(const scene::Palette                &palette,
          Database                            &database,
          Hierarchy                           &level2,
          const std::vector<scene::VoxelGrid> *scene_grids,
          std::ostream                        &out,
          const bool                           show_progress) const;

    /**
     * Lazy mode for a coarse simulation at coarsening @p level (1 or 2):
     * checks the settings (check_simulation_input()) and the blocks of
     * @p grids (check_scene(), before anything is
     * written), locks (lock()) and opens the database, fits the metamaterials
     * the blocks of @p grids (the states of a scene) need at that level if they
     * are missing (appending them to the file), and returns the database, with
     * the level 2 the file has in @p level2 (at level 2, the tables and
     * entries that the blocks of @p grids need).
     */
    Database
    prepare(const scene::Palette                &palette,
            const std::vector<scene::VoxelGrid> &grids,
            const unsigned int                   level,
            Hierarchy                           &level2,
            std::ostream                        &out) const;

    /// Every combination of the palette (Scope = all).
    static std::vector<Combination>
    all_combinations(const Database &database);

    /// The combinations of the 2x2x2 blocks of @p grid (Scope = scene).
    static std::vector<Combination>
    scene_combinations(const scene::VoxelGrid &grid);

    /// The 4x4x4 blocks of @p grid, each as its eight 2x2x2 sub-blocks.
    static std::vector<std::array<Combination, 8>>
    scene_blocks(const scene::VoxelGrid &grid);

    /**
     * Samples and fits the metamaterial of one combination: the 2x2x2
     * block of the palette's materials, its samples (force patterns and,
     * for a mixed block, embedded ones; SamplingSettings::for_block()) from
     * a generator seeded with @p seed, anisotropy directions,
     * and the regularized, bounded fit toward the children's materials,
     * once for @p element with FitSettings::regularization
     * (Entry::material) and once for the element with child_point_offset
     * with FitSettings::child_regularization (Entry::child_material).
     */
    static Entry
    fit_entry(const scene::Palette   &palette,
              const Database         &database,
              const Combination      &combination,
              const SamplingSettings &sampling,
              const FitSettings      &fitting,
              const CoarseElement    &element,
              const std::uint64_t     seed);

  private:
    /**
     * Samples and fits second-level representative @p r of @p level2: its
     * block of eight level-1 metamaterials (their child fits), its samples
     * (SamplingSettings::for_block() of its voxels) from a generator
     * seeded with @p seed, and the 64-point fit toward
     * the children's records (whose directions it keeps).
     */
    static Entry
    fit_level2_entry(const Database         &level1,
                     const Hierarchy        &level2,
                     const unsigned int      r,
                     const SamplingSettings &sampling,
                     const FitSettings      &fitting,
                     const CoarseElement    &element,
                     const std::uint64_t     seed);

    /// Copies a fit's statistics into @p entry, whose n_dropped counts the
    /// sampler's failed solves: the samples the fit left out (the coarse
    /// element inverts under them, or their energy is not finite and
    /// positive) join them, and count in neither the sample count nor the
    /// strain range.
    static void
    record_fit(const FitResult &fit, Entry &entry);

    /// The absolute path of the directory that holds the database file.
    std::string
    directory() const;

    std::string       database_file;
    bool              with_void           = true;
    Scope             run_scope           = Scope::all;
    unsigned int      n_representatives   = 0;
    unsigned int      n_threads           = 0;
    unsigned int      levels              = 1;
    double            coarse_point_offset = solver::gauss_point_offset;
    SamplingSettings  sampling;
    FitSettings       fitting;
    HierarchySettings hierarchy;
  };
} // namespace ddfem::coarsening

#endif
