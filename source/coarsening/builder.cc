#include <deal.II/base/multithread_info.h>
#include <deal.II/base/timer.h>

#include <ddfem/base/files.h>
#include <ddfem/base/parsing.h>
#include <ddfem/base/statistics.h>
#include <ddfem/coarsening/builder.h>
#include <ddfem/coarsening/coarsener.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <filesystem>
#include <iomanip>
#include <mutex>
#include <set>
#include <system_error>
#include <thread>

namespace ddfem::coarsening
{
  void
  DatabaseBuilder::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Database");
    prm.declare_entry("File",
                      "output/database/metamaterials.h5",
                      Patterns::FileName(Patterns::FileName::output),
                      "The metamaterial database (HDF5). A build extends or "
                      "resumes it if it exists (same palette and settings "
                      "required); its journal FILE.journal holds the entries "
                      "finished since the last save, and FILE.lock makes "
                      "runs that use it at the same time take turns.");
    prm.declare_entry("Include void",
                      "true",
                      Patterns::Bool(),
                      "Whether blocks may have void children (void is then a "
                      "palette entry: (n+1)^8 combinations instead of n^8).");
    prm.declare_entry("Scope",
                      "all",
                      Patterns::Selection("all|scene"),
                      "'all' fits every combination of the palette (one fit "
                      "per symmetry orbit). 'scene' fits only the "
                      "combinations of this scene's 2x2x2 blocks (before and "
                      "after each of its material edits) that the file lacks "
                      "and appends them (lazy mode). Run type = database "
                      "only: a simulation (Method = ddfem) always fits only "
                      "what its scene lacks.");
    prm.declare_entry("Representatives",
                      "0",
                      Patterns::Integer(0, 999999999), // as files store it
                      "Compression: keep this many representative "
                      "metamaterials, chosen by farthest point sampling of "
                      "log-energy features, and map every combination to its "
                      "nearest one. 0 keeps every entry. Only with Run type "
                      "= database and Scope = all. Compressing a file drops "
                      "its level 2, which Levels = 2 builds anew.");
    prm.declare_entry("Levels",
                      "1",
                      Patterns::Integer(1, 2),
                      "Coarsening levels to build: 1 (2x2x2 blocks of voxels) "
                      "or 2 (also 4x4x4 blocks, through the staged "
                      "compression of the subsection Level 2). With Scope = "
                      "all, from the complete level 1; with Scope = scene, "
                      "from the level-1 entries in the file, whose staged "
                      "compression keeps the scene's 4x4x4 blocks first; the "
                      "grid must then divide by 4. Run type = database only: "
                      "a simulation fits what its Coarsening levels need.");
    prm.declare_entry("Threads",
                      "0",
                      Patterns::Integer(0),
                      "Worker threads fitting combinations; 0 uses deal.II's "
                      "thread count (all cores unless DEAL_II_NUM_THREADS "
                      "limits it). Results do not depend on it.");
    SamplingSettings::declare_parameters(prm);
    FitSettings::declare_parameters(prm);
    HierarchySettings::declare_parameters(prm);
    prm.leave_subsection();

    prm.enter_subsection("Discretization");
    // Offsets from solver::point_offset_range(level).
    const auto offset_pattern = [](const unsigned int level) {
      const auto [lower, upper] = solver::point_offset_range(level);
      return Patterns::Double(lower, upper);
    };
    prm.declare_entry(
      "Coarse point offset",
      "0.57735026918962576",
      offset_pattern(1),
      "Method = ddfem, naive or average, Coarsening levels = 1: where the "
      "coarse element's 8 points per 2x2x2 block sit, as the fraction of "
      "its half-width "
      "between its centre and each point, in every direction (from 0.25 "
      "up to, not including, 1: the element's bending energy scales with "
      "the offset squared, and below 0.25 it nears a mechanism). 1/sqrt(3) "
      "is the 2-point Gauss rule, the paper's element. Smaller offsets "
      "keep the element's energy under constant strains and lower it under "
      "bending. Metamaterials are fitted for one offset: a database built "
      "with another is rejected.");
    prm.declare_entry(
      "Level-2 point offset",
      format_number(solver::default_level2_point_offset),
      offset_pattern(2),
      "Method = ddfem, naive or average, Coarsening levels = 2: the 64 "
      "points of a 4x4x4 block are those of the 2-point Gauss rule iterated "
      "twice, moved toward the block's centre by the factor offset / "
      "(1/sqrt(3)), so its bending energy scales as at level 1 (from 0.37 "
      "up to, not including, 0.73, rounded in from 0.366 and 0.732, beyond "
      "which some points leave their voxels). 1/sqrt(3) is the paper's "
      "element; the default, 0.4, bends like the fine blocks "
      "(doc/coarsening.md). The second level's "
      "metamaterials are fitted for it, from samples of the level-1 "
      "entries' child fits, which have the Gauss rule whatever the Coarse "
      "point offset; a second level a database file holds for another "
      "offset is fitted anew.");
    prm.leave_subsection();
  }



  void
  DatabaseBuilder::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Database");
    database_file = prm.get("File");
    // A link to a shared file: every save replaces the file it links to,
    // not the link, so that the file stays shared; also before the file's
    // first build, when the link dangles.
    std::filesystem::path file = database_file;
    std::error_code       error;
    for (unsigned int hops = 0;
         hops < 40 && std::filesystem::is_symlink(file, error);
         ++hops)
      {
        const std::filesystem::path target =
          std::filesystem::read_symlink(file, error);
        AssertThrow(!error,
                    ExcMessage("Database/File = " + database_file +
                               ": the link \"" + file.string() +
                               "\" cannot be read: " + error.message() + "."));
        file = target.is_absolute() ? target : file.parent_path() / target;
      }
    AssertThrow(!std::filesystem::is_symlink(file, error),
                ExcMessage("Database/File = " + database_file +
                           ": its symbolic links form a loop (40 of them "
                           "followed)."));
    database_file     = file.string();
    with_void         = prm.get_bool("Include void");
    run_scope         = prm.get("Scope") == "all" ? Scope::all : Scope::scene;
    n_representatives = prm.get_integer("Representatives");
    n_threads         = prm.get_integer("Threads");
    levels            = prm.get_integer("Levels");
    sampling.parse_parameters(prm);
    fitting.parse_parameters(prm);
    hierarchy.parse_parameters(prm);
    prm.leave_subsection();
    prm.enter_subsection("Discretization");
    coarse_point_offset    = prm.get_double("Coarse point offset");
    hierarchy.point_offset = prm.get_double("Level-2 point offset");
    prm.leave_subsection();
    solver::check_point_offset(coarse_point_offset, 1);
    solver::check_point_offset(hierarchy.point_offset, 2);
  }



  void
  DatabaseBuilder::check_input(const scene::Palette &palette,
                               const unsigned int    level) const
  {
    AssertThrow(!database_file.empty(),
                ExcMessage("Database/File must name a file."));
    // A trilinear element's strains at its points are polynomials of
    // degree 2 or less in each coordinate, so small-strain samples fix at
    // most 27 combinations of the 64 points' mu, and of their lambda.
    // Caught here rather than by the first level-2 fit, after level 1.
    AssertThrow(level < 2 || hierarchy.regularization > 0,
                ExcMessage("Database/Level 2/Regularization must be above 0 "
                           "(up to 1e6) where level 2 is fitted, not 0: a "
                           "level-2 element moves its 64 quadrature points "
                           "by its 8 corners, so no samples determine each "
                           "point's parameters. 1e-6 leaves them nearly "
                           "free."));
    // A block's samples take about 0.17 ms each to solve and fit on two
    // cores (the 1995 blocks of 2500 samples of a database with void took
    // 13.8 min): 100000 per block take 9 hours for such a database.
    AssertThrow(std::size_t(sampling.n_directions) * sampling.n_magnitudes <=
                  100000,
                ExcMessage("Database/Sampling/Patterns x Magnitudes = " +
                           std::to_string(sampling.n_directions) + " x " +
                           std::to_string(sampling.n_magnitudes) +
                           " samples per block exceeds 100000 (40 times the "
                           "paper's 500 x 5: hours for a full database)."));
    // The held-out split takes every n-th pattern of each kind (a mixed
    // block's embedded and force patterns are numbered apart), so each kind
    // a block may have needs n patterns at least.
    const unsigned int n_embedded = sampling.n_embedded();
    unsigned int       fewest     = sampling.n_directions;
    for (const unsigned int n_of_kind :
         {n_embedded, sampling.n_directions - n_embedded})
      if (n_of_kind > 0)
        fewest = std::min(fewest, n_of_kind);
    AssertThrow(fitting.held_out_every <= fewest,
                ExcMessage(
                  "Database/Fitting/Held-out every = " +
                  std::to_string(fitting.held_out_every) + " exceeds the " +
                  std::to_string(fewest) +
                  " patterns of a kind (Database/Sampling/Patterns = " +
                  std::to_string(sampling.n_directions) +
                  ", Embedded fraction = " +
                  Utilities::to_string(sampling.embedded) +
                  "): no pattern of that kind would be held out, and "
                  "a block's held-out errors could be those of its "
                  "fitted samples. Set it to at most " +
                  std::to_string(fewest) +
                  ", or to 0 to measure the errors on the fitted "
                  "samples."));
    AssertThrow(n_representatives == 0 || run_scope == Scope::all,
                ExcMessage("Database/Representatives (compression) needs "
                           "Database/Scope = all: only a complete database "
                           "can be compressed."));
    const unsigned int n_ids = palette.size() + (with_void ? 1 : 0);
    AssertThrow(n_ids <= 9,
                ExcMessage("Metamaterial databases support at most 9 "
                           "material ids (9^8 combinations): 8 materials "
                           "plus void, or 9 with Database/Include void = "
                           "false; Materials has " +
                           std::to_string(palette.size()) + "."));
    palette.require_nonnegative_lambda(
      "Fitting metamaterials (Run type = database, Method = ddfem)");
    // (A path that cannot be followed is check_creatable()'s to report.)
    std::error_code   error;
    const std::string name =
      std::filesystem::path(database_file).filename().string();
    AssertThrow(name != "" && name != "." && name != ".." &&
                  !std::filesystem::is_directory(database_file, error),
                ExcMessage(
                  "Database/File = '" + database_file +
                  "' names a directory; give the name of a file "
                  "(e.g. " +
                  (std::filesystem::path(database_file) / "metamaterials.h5")
                    .lexically_normal()
                    .string() +
                  ")."));
    check_creatable(directory(), "Database/File");
  }



  DatabaseSettings
  DatabaseBuilder::settings(const scene::Palette &palette) const
  {
    DatabaseSettings settings;
    settings.palette      = DatabaseSettings::describe(palette);
    settings.with_void    = with_void;
    settings.sampling     = sampling;
    settings.fitting      = fitting;
    settings.point_offset = coarse_point_offset;
    return settings;
  }



  std::string
  DatabaseBuilder::directory() const
  {
    return std::filesystem::absolute(database_file).parent_path().string();
  }



  void
  DatabaseBuilder::check_scene(const scene::Palette                &palette,
                               const std::vector<scene::VoxelGrid> &grids) const
  {
    check_input(palette, levels);
    // A database of these settings covers what their numbering does (its
    // tables, one entry per combination, are not needed for that).
    const CombinationIndex index(palette.size(), with_void);
    for (const scene::VoxelGrid &grid : grids)
      {
        scene::check_coarsenable(grid, levels);
        for (const Combination &c : scene_combinations(grid))
          index.check_covered(c);
        if (levels == 2)
          for (const auto &block : scene_blocks(grid))
            Hierarchy::check_representable(index, block);
      }
  }



  void
  DatabaseBuilder::check_simulation_input(const scene::Palette &palette,
                                          const unsigned int    level) const
  {
    AssertThrow(n_representatives == 0,
                ExcMessage("Database/Representatives = " +
                           std::to_string(n_representatives) +
                           " compresses a complete database, which Run type "
                           "= database builds (Database/Scope = all). A "
                           "simulation fits only the blocks its scene lacks "
                           "and compresses nothing: set it to 0 here, and "
                           "compress the file with Run type = database."));
    check_input(palette, level);
  }



  std::unique_ptr<FileLock>
  DatabaseBuilder::lock(const scene::Palette &palette, std::ostream &out) const
  {
    check_input(palette, levels);
    const std::filesystem::path file = resolved_path(database_file);
    // Before anything is fitted: the file, its journals and their
    // temporaries must be regular files or missing. A directory there
    // failed only at the save, and a named pipe made the read wait forever.
    // Only looked at, so that no file is made or removed before the lock.
    for (const std::string &path : database_files(file.string()))
      {
        const std::string kind = non_regular_kind(path);
        AssertThrow(kind.empty(),
                    ExcMessage("Database/File = " + database_file + ": \"" +
                               path + "\", which a build reads or writes, is " +
                               kind +
                               ". Remove it, or use another Database/File."));
      }
    create_directories(file.parent_path().string(), "Database/File");
    return std::make_unique<FileLock>(file.string() + ".lock",
                                      "Database/File",
                                      out);
  }



  Database
  DatabaseBuilder::open(const scene::Palette &palette,
                        Hierarchy            &level2,
                        std::ostream         &out) const
  {
    check_input(palette, levels);
    const DatabaseSettings settings = this->settings(palette);

    Database database(settings, palette.size());
    level2 = Hierarchy();
    if (std::filesystem::exists(database_file))
      {
        database = Database::load(database_file, &level2);
        AssertThrow(database.palette() == settings.palette,
                    ExcMessage("The metamaterial database '" + database_file +
                               "' was built for the palette [" +
                               database.palette() +
                               "], not for this scene's [" + settings.palette +
                               "]. Use another Database/File."));
        AssertThrow(database.fingerprint() == settings.fingerprint(),
                    ExcMessage("The metamaterial database '" + database_file +
                               "' was built with other settings (" +
                               settings_difference(database.fingerprint(),
                                                   settings.fingerprint()) +
                               "). Use another Database/File or its "
                               "settings."));
      }
    const std::vector<Entry> journaled = Journal::read(
      database_file, settings.fingerprint(), database.combinations().size(), 1);
    unsigned int recovered = 0;
    for (const Entry &e : journaled)
      {
        const Combination c = database.combinations().combination(e.key);
        AssertThrow(database.symmetries().canonical(c).first == c,
                    ExcMessage("The build journal " + database_file +
                               ".journal holds an entry for combination " +
                               std::to_string(e.key) +
                               ", which is not its symmetry orbit's "
                               "representative: the journal is damaged. "
                               "Delete it (the entries it held are fitted "
                               "again)."));
        if (!database.contains(c))
          {
            database.add(e);
            ++recovered;
          }
      }
    if (recovered > 0)
      out << "Resumed: " << recovered
          << " entries recovered from the build journal" << std::endl;
    return database;
  }



  std::vector<Combination>
  DatabaseBuilder::all_combinations(const Database &database)
  {
    std::vector<Combination> result;
    for (std::size_t key = 0; key < database.combinations().size(); ++key)
      result.push_back(database.combinations().combination(key));
    return result;
  }



  std::vector<Combination>
  DatabaseBuilder::scene_combinations(const scene::VoxelGrid &grid)
  {
    scene::check_coarsenable(grid, 1);
    const auto              &n = grid.size();
    std::vector<Combination> result;
    for (unsigned int k = 0; k < n[2]; k += 2)
      for (unsigned int j = 0; j < n[1]; j += 2)
        for (unsigned int i = 0; i < n[0]; i += 2)
          result.push_back(Coarsener::combination(grid, i, j, k));
    return result;
  }



  Entry
  DatabaseBuilder::fit_entry(const scene::Palette   &palette,
                             const Database         &database,
                             const Combination      &combination,
                             const SamplingSettings &sampling,
                             const FitSettings      &fitting,
                             const CoarseElement    &element,
                             const std::uint64_t     seed)
  {
    std::array<std::vector<material::MaterialPoint>, 8> children;
    Metamaterial                                        prior;
    for (unsigned int k = 0; k < 8; ++k)
      {
        material::MaterialPoint p; // void: all zero
        if (combination[k] != scene::void_id)
          {
            p = palette[combination[k]].material_point();
            children[k].assign(8, p);
          }
        prior.points.push_back(p);
      }
    const BlockSampler sampler(children);
    Entry              entry;
    entry.key = database.combinations().key(combination);
    const SamplingSettings block_sampling =
      sampling.for_block({combination.begin(), combination.end()});
    const std::vector<Sample> samples =
      sampler.sample(block_sampling, seed, entry.n_dropped);
    const std::optional<unsigned int> axis =
      fitting.laminate_springs ? split_axis(combination) : std::nullopt;
    // The least-squares problem of the samples for the points of element
    // @p e: the prior's directions, and the ties of the block's symmetries.
    const auto problem = [&](const CoarseElement &e) {
      Metamaterial m = prior;
      PointTies    ties;
      if (axis)
        ties = laminate_springs(m, *axis);
      else
        {
          const std::vector<Tensor<1, 3>> directions =
            sampler.anisotropy_directions(block_sampling, e);
          for (unsigned int q = 0; q < 8; ++q)
            m.points[q].direction = directions[q];
          ties = symmetrize_directions(m, combination, database.symmetries());
        }
      return MetamaterialFit(e, samples, m, fitting, ties);
    };
    const MetamaterialFit coarse = problem(element);
    const FitResult       fit =
      coarse.fit(fitting.regularization, fitting.spring_regularization);
    entry.material = fit.material;
    record_fit(fit, entry);
    // The child fit solves the same problem where the offsets agree.
    entry.child_material = element.point_offset() == child_point_offset ?
                             coarse.parameters(fitting.child_regularization) :
                             problem(CoarseElement(1, child_point_offset))
                               .parameters(fitting.child_regularization);
    return entry;
  }



  Entry
  DatabaseBuilder::fit_level2_entry(const Database         &level1,
                                    const Hierarchy        &level2,
                                    const unsigned int      r,
                                    const SamplingSettings &sampling,
                                    const FitSettings      &fitting,
                                    const CoarseElement    &element,
                                    const std::uint64_t     seed)
  {
    // The children are level-1 elements with the child fits' offset, and
    // blocks of voxels. The sampling follows the block's 64 voxels: a void
    // voxel inside a child puts the block on a part's surface even if no
    // child is void.
    const std::array<Combination, 8> blocks = level2.composition(level1, r);
    std::array<std::vector<material::MaterialPoint>, 8> children;
    std::vector<scene::MaterialId>                      voxels;
    BlockSampler::VoidVoxels                            void_voxels{};
    for (unsigned int k = 0; k < 8; ++k)
      {
        if (!all_void(blocks[k]))
          children[k] = level1.lookup(blocks[k], Fit::child).points;
        for (unsigned int j = 0; j < 8; ++j)
          {
            voxels.push_back(blocks[k][j]);
            if (blocks[k][j] == scene::void_id)
              void_voxels[k] |= 1u << j;
          }
      }
    // Point q starts from its child's sub-point and keeps its direction.
    Metamaterial prior;
    for (unsigned int q = 0; q < element.n_points(); ++q)
      {
        const auto             &child = children[element.child_of_point(q)];
        material::MaterialPoint p;
        p.direction[0] = 1;
        if (!child.empty())
          p = child[element.subpoint_of_point(q)];
        prior.points.push_back(p);
      }
    const BlockSampler sampler(children, child_point_offset, void_voxels);
    Entry              entry;
    const std::vector<Sample> samples =
      sampler.sample(sampling.for_block(voxels), seed, entry.n_dropped);
    const FitResult fit = fit_metamaterial(element, samples, prior, fitting);
    entry.key           = r;
    entry.material      = fit.material;
    record_fit(fit, entry);
    return entry;
  }



  void
  DatabaseBuilder::record_fit(const FitResult &fit, Entry &entry)
  {
    entry.median_error = fit.median_error;
    entry.max_error    = fit.max_error;
    entry.n_samples    = fit.n_fit + fit.n_held_out;
    entry.n_dropped += fit.n_rejected;
    entry.min_strain = fit.min_strain;
    entry.max_strain = fit.max_strain;
  }



  void
  fit_in_parallel(const std::size_t                              n,
                  const unsigned int                             n_threads,
                  const std::function<Entry(const std::size_t)> &fit,
                  const std::function<void(const Entry &)>      &store,
                  std::ostream                                  &out,
                  const bool                                     show_progress)
  {
    Timer                    timer;
    std::mutex               mutex;
    std::atomic<std::size_t> next(0);
    std::size_t              done      = 0;
    double                   last_draw = -1;
    const unsigned int       workers   = std::max<std::size_t>(
      1,
      std::min<std::size_t>(n_threads > 0 ? n_threads :
                                                    MultithreadInfo::n_threads(),
                            n));
    // The first error in any worker stops the others; it is rethrown
    // once all have joined, so entries stored before it stay stored.
    std::exception_ptr error;
    const auto         work = [&]() {
      for (std::size_t i = next++; i < n; i = next++)
        try
          {
            const Entry                 entry = fit(i);
            std::lock_guard<std::mutex> lock(mutex);
            store(entry);
            ++done;
            // The progress bar, redrawn at most every half second.
            if (show_progress &&
                (timer.wall_time() > last_draw + 0.5 || done == n))
              {
                last_draw               = timer.wall_time();
                const double       left = last_draw / done * (n - done);
                const unsigned int width = 30;
                const unsigned int bar   = width * done / n;
                out << "\r  [" << std::string(bar, '#')
                    << std::string(width - bar, ' ') << "] " << done << "/" << n
                    << ", " << std::fixed << std::setprecision(0) << last_draw
                    << " s, about " << left << " s left   " << std::defaultfloat
                    << std::setprecision(6) << std::flush;
              }
          }
        catch (...)
          {
            std::lock_guard<std::mutex> lock(mutex);
            if (!error)
              error = std::current_exception();
            next = n;
          }
    };
    // Should the system refuse a thread, fewer workers do the job: the
    // results do not depend on their number. (Reserved first: a vector
    // that failed to grow would leave the running threads unjoined.)
    std::vector<std::thread> threads;
    threads.reserve(workers);
    for (unsigned int t = 1; t < workers; ++t)
      try
        {
          threads.emplace_back(work);
        }
      catch (const std::system_error &)
        {
          break;
        }
    work();
    for (auto &t : threads)
      t.join();
    if (show_progress && n > 0)
      out << std::endl;
    if (error)
      std::rethrow_exception(error);
  }



  namespace
  {
    /**
     * fit_in_parallel() with every entry appended to the journal of
     * @p journal_of (Journal, with @p fingerprint, @p n_keys and @p level)
     * before store() takes it, so that a killed build resumes, as does one
     * stopped by another error (a full disk). A build stopped by a fit its
     * settings cannot give (ExcFitRefused) removes a journal it started:
     * the same settings fail that fit again, and other settings refuse the
     * journal. A journal it resumed may hold another scene's fits, which
     * those settings give, and stays.
     */
    void
    fit_journaled(const std::string                             &journal_of,
                  const std::string                             &fingerprint,
                  const std::size_t                              n_keys,
                  const unsigned int                             level,
                  const std::size_t                              n,
                  const unsigned int                             n_threads,
                  const std::function<Entry(const std::size_t)> &fit,
                  const std::function<void(const Entry &)>      &store,
                  std::ostream                                  &out,
                  const bool                                     show_progress)
    {
      const bool started = !Journal::exists(journal_of);
      try
        {
          Journal journal(journal_of, fingerprint, n_keys, level);
          fit_in_parallel(
            n,
            n_threads,
            fit,
            [&](const Entry &entry) {
              journal.append(entry);
              store(entry);
            },
            out,
            show_progress);
        }
      catch (const ExcFitRefused &)
        {
          std::error_code ignored; // the refusal is the error to report
          if (started)
            std::filesystem::remove(Journal::file_name(journal_of), ignored);
          throw;
        }
    }


    /// Prints the statistics of a level's entries.
    void
    report(const std::vector<Entry> &entries, std::ostream &out)
    {
      std::vector<double> errors;
      double              min_strain = 1e300, max_strain = 0;
      std::size_t         samples = 0, dropped = 0;
      for (const Entry &e : entries)
        {
          errors.push_back(e.median_error);
          min_strain = std::min(min_strain, e.min_strain);
          max_strain = std::max(max_strain, e.max_strain);
          samples += e.n_samples;
          dropped += e.n_dropped;
        }
      out << "  entries: " << entries.size() << ", samples kept: " << samples
          << ", dropped (failed solves, or the coarse element inverts): "
          << dropped << std::endl;
      if (errors.empty())
        return;
      std::sort(errors.begin(), errors.end());
      out << std::setprecision(3) << "  strain range sampled: " << min_strain
          << " to " << max_strain << " (largest principal stretch deviation)\n"
          << "  held-out relative energy error per entry (median of each): "
          << "10% " << quantile(errors, 0.1) << ", 50% "
          << quantile(errors, 0.5) << ", 90% " << quantile(errors, 0.9)
          << ", max " << errors.back() << std::setprecision(6) << std::endl;
    }



    /**
     * Adds to @p level2 the fits that the journal of @p journal_of
     * (Journal::read() with @p fingerprint) holds and @p level2 lacks, keeps
     * its entries sorted by key, and returns the number of records the
     * journal holds: the fits of a level-2 build killed before its save,
     * under these tables. A build saves them like new ones.
     */
    std::size_t
    add_journaled(Hierarchy         &level2,
                  const std::string &journal_of,
                  const std::string &fingerprint)
    {
      const std::vector<Entry> journaled =
        Journal::read(journal_of, fingerprint, level2.n_representatives(), 2);
      level2.entries.insert(level2.entries.end(),
                            journaled.begin(),
                            journaled.end());
      // Of a key held twice, the first: the file's fit.
      sort_by_key(level2.entries);
      level2.entries.erase(std::unique(level2.entries.begin(),
                                       level2.entries.end(),
                                       [](const Entry &a, const Entry &b) {
                                         return a.key == b.key;
                                       }),
                           level2.entries.end());
      return journaled.size();
    }



    /**
     * Reports how many of a scene state's level-1 blocks (@p blocks,
     * all-void ones aside) a plane splits into two one-voxel layers
     * (split_axis()). Without laminate springs such blocks fit too soft along
     * their layers; where they make up most of the part, the report says so and
     * names the setting. A cantilever of one-voxel layers along its axis, all
     * its blocks split, bends 3.4 to 3.9 times as far as the fine one without
     * them; the shipped scenes, with 2 % to 19 % of their blocks split, are
     * better off without (doc/coarsening.md, "Layers one voxel thick along
     * a part").
     */
    void
    report_split_blocks(const std::vector<Combination> &blocks,
                        const bool                      laminate_springs,
                        std::ostream                   &out)
    {
      std::size_t n_solid = 0, n_split = 0;
      for (const Combination &c : blocks)
        if (!all_void(c))
          {
            ++n_solid;
            n_split += split_axis(c).has_value();
          }
      if (n_split == 0)
        return;
      out << "  " << n_split << " of the " << n_solid
          << " blocks of the scene's base state are split into two one-voxel "
             "layers (Database/Fitting/Laminate springs = "
          << (laminate_springs ? "true" : "false") << ")" << std::endl;
      if (!laminate_springs && 2 * n_split > n_solid)
        out << "  Note: most blocks are split into two layers. Without "
               "laminate springs their fits are far too soft along the "
               "layers, so a part that bends or stretches along them comes "
               "out far too soft at level 1 (doc/coarsening.md, 'Layers one "
               "voxel thick along a part'); Database/Fitting/Laminate "
               "springs = true fits them as laminates."
            << std::endl;
    }
  } // namespace



  void
  DatabaseBuilder::build(const scene::Palette                &palette,
                         Database                            &database,
                         Hierarchy                           &level2,
                         const std::vector<scene::VoxelGrid> *scene_grids,
                         std::ostream                        &out,
                         const bool show_progress) const
  {
    Timer timer;
    // The scene's 4x4x4 blocks and their keys, for the level-2 tables. A
    // grid that level 2 cannot coarsen, or a block it cannot represent
    // (Hierarchy::keys() checks), is an error before anything is fitted
    // (and journaled).
    std::vector<std::array<Combination, 8>> level2_blocks;
    std::vector<BlockKeys>                  block_keys;
    if (scene_grids != nullptr && levels == 2)
      for (const scene::VoxelGrid &grid : *scene_grids)
        for (const auto &b : scene_blocks(grid))
          {
            level2_blocks.push_back(b);
            block_keys.push_back(Hierarchy::keys(database, b));
          }
    std::vector<Combination> wanted;
    // The blocks of the scene's base state (its edits repaint some of them).
    std::vector<Combination> base_blocks;
    if (scene_grids == nullptr)
      wanted = all_combinations(database);
    else
      for (const scene::VoxelGrid &grid : *scene_grids)
        {
          std::vector<Combination> blocks = scene_combinations(grid);
          wanted.insert(wanted.end(), blocks.begin(), blocks.end());
          if (&grid == &scene_grids->front())
            base_blocks = std::move(blocks);
        }
    const std::vector<Combination> todo = database.missing(wanted);
    // The file's level 2 (open() read and checked it): a level-1 build
    // keeps it, since its tables and fits are keyed by combination and new
    // level-1 entries leave them valid (a level-2 build renews tables that
    // do not cover them).
    // The entries open() recovered from the journal of a build killed
    // before its save are in @p database but perhaps not in the file: a
    // journal makes the build save, which retires it.
    const bool journaled = Journal::exists(database_file);
    out << "Metamaterial database '" << database_file
        << "', level 1: " << database.combinations().size() << " combinations, "
        << database.entries().size() << " entries present, " << todo.size()
        << " orbit representatives to fit" << std::endl;
    report_split_blocks(base_blocks, fitting.laminate_springs, out);
    AssertThrow(todo.empty() || database.n_representatives() == 0,
                ExcMessage("The metamaterial database '" + database_file +
                           "' is compressed and cannot take new entries."));
    AssertThrow(n_representatives == 0 || database.n_representatives() == 0 ||
                  database.n_representatives() == n_representatives,
                ExcMessage("The metamaterial database '" + database_file +
                           "' was compressed with Database/Representatives "
                           "= " +
                           std::to_string(database.n_representatives()) +
                           ", not " + std::to_string(n_representatives) +
                           ". Set that number, or 0, or build into another "
                           "Database/File."));

    const CoarseElement element(1, database.point_offset());
    if (!todo.empty())
      {
        Database::check_not_read_only(database_file);
        create_directories(directory(), "Database/File");
        fit_journaled(
          database_file,
          database.fingerprint(),
          database.combinations().size(),
          1,
          todo.size(),
          n_threads,
          [&](const std::size_t i) {
            // A seed per combination: entries do not depend on threads.
            const std::size_t key = database.combinations().key(todo[i]);
            return fit_entry(palette,
                             database,
                             todo[i],
                             sampling,
                             fitting,
                             element,
                             0x9E3779B97F4A7C15ULL *
                               (key + 1 + sampling.seed * 1000003ULL));
          },
          [&](const Entry &entry) { database.add(entry); },
          out,
          show_progress);
      }
    const double level1_time = timer.wall_time();

    const bool compressed_now =
      (n_representatives > 0 && database.n_representatives() == 0);
    if (compressed_now)
      {
        const unsigned int n_picked =
          database.compress(n_representatives,
                            element,
                            compression_deformations());
        out << "Compressed to " << n_picked << " representatives ("
            << database.entries().size() << " entries kept)" << std::endl;
      }

    // Level 2: the staged tables first (saved before any fit, so a
    // resumed build finds them), then the representatives' fits.
    // A scene's blocks are required in the tables: each is then fitted as
    // it is. Tables that predate a level-1 entry or a block this build
    // needs (lazy mode) are built anew; they keep the blocks required
    // before, and the fits of compositions they still represent. A build
    // for no scene (Scope = all) makes tables that require no block, which
    // represent every block and so serve every later scene: it renews
    // tables that earlier lazy runs made, and drops their blocks.
    bool new_tables = false;
    // Compression changes the level-1 models level 2 was sampled from.
    if (compressed_now && !level2.empty())
      {
        out << "Level 2 (" << level2.entries.size()
            << " fits) dropped: it was sampled from the level-1 entries "
               "before the compression"
            << (levels == 2 ? "; it is built anew." :
                              "; Database/Levels = 2 builds it anew.")
            << std::endl;
        level2 = Hierarchy();
      }
    const std::string level2_journal = level2_journal_base(database_file);
    // A level-2 journal holds fits of these level-1 entries and level-2
    // settings.
    const auto journal_fingerprint = [&](const HierarchySettings &settings) {
      return database.fingerprint() + " | " + settings.fingerprint();
    };
    const std::string level2_fingerprint = journal_fingerprint(hierarchy);
    if (levels == 2)
      {
        if (level2.empty() ||
            level2.settings.fingerprint() != hierarchy.fingerprint() ||
            !level2.covers(database, wanted, block_keys) ||
            (scene_grids == nullptr && !level2.required_blocks().empty()))
          {
            Hierarchy  old  = std::move(level2);
            const bool keep = !old.empty() && old.settings.fits_like(hierarchy);
            if (!old.empty() && !keep && !old.entries.empty())
              out << "Level 2: the file's " << old.entries.size()
                  << " fits were made with other settings ("
                  << settings_difference(old.settings.fingerprint(),
                                         hierarchy.fingerprint())
                  << ") and are dropped." << std::endl;
            // The fits a killed build journaled are kept like the file's,
            // but their keys index the old tables: the file takes them with
            // those tables before the journal goes.
            if (keep && add_journaled(old,
                                      level2_journal,
                                      journal_fingerprint(old.settings)) > 0)
              database.save(database_file, &old);
            Journal::remove(level2_journal);
            if (scene_grids != nullptr)
              block_keys.insert(block_keys.end(),
                                old.required_blocks().begin(),
                                old.required_blocks().end());
            level2 = Hierarchy();
            level2.build_tables(database, hierarchy, block_keys);
            if (keep)
              level2.keep_entries(database, old);
            new_tables = true;
          }
      }
    if (!todo.empty() || journaled || compressed_now || new_tables ||
        !std::filesystem::exists(database_file))
      {
        create_directories(directory(), "Database/File");
        database.save(database_file, &level2);
        Journal::remove(database_file);
      }
    report(database.entries(), out);
    if (show_progress)
      out << "  level 1 fitting time: " << level1_time << " s ("
          << (todo.empty() ? 0. : level1_time / todo.size())
          << " s per combination)" << std::endl;

    if (levels == 2)
      {
        // The scene's distinct blocks, and those that are their own
        // representative (all, unless they exceed the budgets).
        std::vector<unsigned int>            needed;
        std::set<std::array<Combination, 8>> distinct;
        std::size_t                          n_own = 0;
        if (scene_grids == nullptr)
          for (unsigned int r = 0; r < level2.n_representatives(); ++r)
            needed.push_back(r);
        else
          for (const auto &block : level2_blocks)
            if (const int r = level2.find(database, block); r >= 0)
              {
                needed.push_back(r);
                if (distinct.insert(block).second &&
                    level2.composition(database, r) == block)
                  ++n_own;
              }
        const auto has = [&level2](const std::size_t r) {
          return has_key(level2.entries, r);
        };
        const std::size_t n_journaled =
          add_journaled(level2, level2_journal, level2_fingerprint);
        std::sort(needed.begin(), needed.end());
        needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
        needed.erase(std::remove_if(needed.begin(), needed.end(), has),
                     needed.end());
        out << "Level 2: " << level2.n_representatives() << " representatives, "
            << level2.entries.size() << " fitted, " << needed.size()
            << " to fit" << std::endl;
        if (scene_grids != nullptr)
          {
            out << "  " << n_own << " of " << distinct.size()
                << " distinct 4x4x4 blocks fitted as they are";
            if (n_own < distinct.size())
              out << (level2.required_blocks().empty() ?
                        "; the others take the nearest representative's "
                        "fit of the file's tables, which a build with "
                        "Scope = all made for every composition" :
                        "; the others exceed the Level 2 budgets and share "
                        "the nearest representative's fit");
            out << std::endl;
          }

        const CoarseElement element2(2, hierarchy.point_offset);
        FitSettings         fitting2 = fitting;
        fitting2.regularization      = hierarchy.regularization;
        Timer timer2;
        if (!needed.empty())
          {
            Database::check_not_read_only(database_file);
            fit_journaled(
              level2_journal,
              level2_fingerprint,
              level2.n_representatives(),
              2,
              needed.size(),
              n_threads,
              [&](const std::size_t i) {
                // A seed per composition: a fit does not depend on the
                // representative's index in the current tables.
                std::uint64_t seed =
                  0x2545F4914F6CDD1DULL + sampling.seed * 7919ULL;
                for (const std::int64_t key :
                     Hierarchy::keys(database,
                                     level2.composition(database, needed[i])))
                  seed = (seed ^ std::uint64_t(key + 1)) * 0x100000001B3ULL;
                return fit_level2_entry(database,
                                        level2,
                                        needed[i],
                                        sampling,
                                        fitting2,
                                        element2,
                                        seed);
              },
              [&](const Entry &entry) { level2.entries.push_back(entry); },
              out,
              show_progress);
          }
        sort_by_key(level2.entries);
        if (!needed.empty() || n_journaled > 0)
          {
            database.save(database_file, &level2);
            Journal::remove(level2_journal);
          }
        report(level2.entries, out);
        if (show_progress)
          out << "  level 2 fitting time: " << timer2.wall_time() << " s ("
              << (needed.empty() ? 0. : timer2.wall_time() / needed.size())
              << " s per representative)" << std::endl;
      }
    if (show_progress)
      out << "  total time: " << timer.wall_time() << " s, file size: "
          << std::filesystem::file_size(database_file) / 1024. << " KiB"
          << std::endl;
  }



  Database
  DatabaseBuilder::prepare(const scene::Palette                &palette,
                           const std::vector<scene::VoxelGrid> &grids,
                           const unsigned int                   level,
                           Hierarchy                           &level2,
                           std::ostream                        &out) const
  {
    check_simulation_input(palette, level);
    DatabaseBuilder lazy(*this);
    lazy.levels            = level;
    lazy.run_scope         = Scope::scene;
    lazy.n_representatives = 0; // only a complete database is compressed
    lazy.check_scene(palette, grids);
    const auto held     = lazy.lock(palette, out);
    Database   database = lazy.open(palette, level2, out);
    lazy.build(palette, database, level2, &grids, out, false);
    return database;
  }



  std::vector<std::array<Combination, 8>>
  DatabaseBuilder::scene_blocks(const scene::VoxelGrid &grid)
  {
    scene::check_coarsenable(grid, 2);
    const auto                             &n = grid.size();
    std::vector<std::array<Combination, 8>> result;
    for (unsigned int k = 0; k < n[2]; k += 4)
      for (unsigned int j = 0; j < n[1]; j += 4)
        for (unsigned int i = 0; i < n[0]; i += 4)
          result.push_back(Coarsener::sub_blocks(grid, i, j, k));
    return result;
  }
} // namespace ddfem::coarsening
