// The metamaterial database: symmetry orbits and the mapping of fitted
// entries, farthest point sampling, HDF5 round trip, clear errors for
// missing, corrupt, truncated, damaged and mismatched files, a killed and
// resumed build equal to an uninterrupted one, results independent of the
// thread count, lazy (scene) builds, and compression.

#include <ddfem/base/exceptions.h>
#include <ddfem/coarsening/builder.h>
#include <fcntl.h>
#include <hdf5.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <set>
#include <tuple>
#include <type_traits>

#include "../tests.h"

using namespace ddfem;
using namespace ddfem::coarsening;

namespace
{
  /// A small palette and cheap sampling: every test build takes a second.
  /// @p extra is parameter text read last.
  DatabaseBuilder
  builder(const std::string &file,
          const bool         with_void,
          const std::string &scope    = "all",
          const unsigned int threads  = 1,
          const unsigned int k        = 0,
          const unsigned int levels   = 1,
          const unsigned int patterns = 30,
          const unsigned int seed     = 0,
          const std::string &extra    = "")
  {
    ParameterHandler prm;
    DatabaseBuilder::declare_parameters(prm);
    prm.enter_subsection("Database");
    prm.set("File", file);
    prm.set("Include void", with_void);
    prm.set("Scope", scope);
    prm.set("Threads", std::to_string(threads));
    prm.set("Representatives", std::to_string(k));
    prm.set("Levels", std::to_string(levels));
    prm.enter_subsection("Level 2");
    prm.set("Level-1 classes", "20");
    prm.set("Intermediate representatives", "20");
    prm.set("Representatives", "10");
    prm.leave_subsection();
    prm.enter_subsection("Sampling");
    prm.set("Patterns", std::to_string(patterns));
    prm.set("Magnitudes", "2");
    prm.set("Stretch directions", "20");
    prm.set("Seed", std::to_string(seed));
    prm.leave_subsection();
    // Blocks split in two layers get their own springs, whose lookups
    // commute with the symmetries only up to a mirror (tested below).
    prm.enter_subsection("Fitting");
    prm.set("Laminate springs", true);
    prm.leave_subsection();
    prm.leave_subsection();
    prm.parse_input_from_string(extra);
    DatabaseBuilder b;
    b.parse_parameters(prm);
    return b;
  }

  scene::Palette
  palette(const std::string &text = "E=1e5 nu=0.45; E=1e6 nu=0.45")
  {
    scene::Palette p;
    p.parse(text);
    return p;
  }

  /// The database of @p b for @p p, opened (DatabaseBuilder::open()); its
  /// second level is read and checked, and dropped.
  Database
  open(const DatabaseBuilder &b, const scene::Palette &p, std::ostream &log)
  {
    Hierarchy level2;
    return b.open(p, level2, log);
  }

  Database
  build(const DatabaseBuilder &b, const scene::Palette &p)
  {
    std::ostringstream log;
    Hierarchy          level2;
    Database           db = b.open(p, level2, log);
    b.build(p, db, level2, nullptr, log, false);
    return db;
  }

  /// Both levels of palette() without void built into @p file with Scope
  /// @p scope, for the blocks of @p grids (no scene if null); the second
  /// level in @p level2 if given, and the build's line on the scene's
  /// distinct 4x4x4 blocks in @p distinct_line if given.
  Database
  build_levels(const std::string                   &file,
               const std::string                   &scope,
               const std::vector<scene::VoxelGrid> *grids,
               Hierarchy                           *level2        = nullptr,
               std::string                         *distinct_line = nullptr)
  {
    std::ostringstream    log;
    const DatabaseBuilder b = builder(file, false, scope, 1, 0, 2);
    Hierarchy             opened;
    Database              db = b.open(palette(), opened, log);
    b.build(palette(), db, opened, grids, log, false);
    if (level2 != nullptr)
      *level2 = std::move(opened);
    std::istringstream lines(log.str());
    for (std::string line;
         distinct_line != nullptr && std::getline(lines, line);)
      if (line.find("distinct 4x4x4 blocks") != std::string::npos)
        *distinct_line = line;
    return db;
  }

  bool
  same_points(const Metamaterial &a, const Metamaterial &b)
  {
    if (a.points.size() != b.points.size())
      return false;
    for (unsigned int q = 0; q < a.points.size(); ++q)
      {
        const auto &p = a.points[q];
        const auto &r = b.points[q];
        if (p.mu != r.mu || p.lambda != r.lambda ||
            p.anisotropy != r.anisotropy || p.direction != r.direction)
          return false;
      }
    return true;
  }

  /// The same entries (keys, both fits, fit statistics) and the same
  /// metamaterial for every combination either database has.
  bool
  same_entries(const Database &a, const Database &b)
  {
    if (a.entries().size() != b.entries().size())
      return false;
    for (unsigned int e = 0; e < a.entries().size(); ++e)
      {
        const Entry &x = a.entries()[e], &y = b.entries()[e];
        if (x.key != y.key || !same_points(x.material, y.material) ||
            !same_points(x.child_material, y.child_material) ||
            x.median_error != y.median_error || x.max_error != y.max_error ||
            x.min_strain != y.min_strain || x.max_strain != y.max_strain ||
            x.n_samples != y.n_samples || x.n_dropped != y.n_dropped)
          return false;
      }
    const auto combinations = DatabaseBuilder::all_combinations(a);
    if (combinations != DatabaseBuilder::all_combinations(b))
      return false;
    for (const Combination &c : combinations)
      if (a.contains(c) != b.contains(c) ||
          (a.contains(c) &&
           (!same_points(a.lookup(c), b.lookup(c)) ||
            !same_points(a.lookup(c, Fit::child), b.lookup(c, Fit::child)))))
        return false;
    return true;
  }

  /// The same level-2 entries: keys and metamaterials.
  bool
  same_level2_entries(const std::vector<Entry> &a, const std::vector<Entry> &b)
  {
    bool same = (a.size() == b.size());
    for (unsigned int e = 0; same && e < a.size(); ++e)
      same =
        (a[e].key == b[e].key && same_points(a[e].material, b[e].material));
    return same;
  }

  /**
   * Copies @p original to @p copy and passes the values and the shape of
   * its dataset @p name (of HDF5 type @p type) to @p edit, which may change
   * both; the dataset is then written anew, compressed (chunks and deflate,
   * as h5repack -f GZIP writes it) if @p compress.
   */
  template <typename T>
  void
  edit_dataset(
    const std::string &original,
    const std::string &copy,
    const std::string &name,
    const std::function<void(std::vector<T> &, std::vector<hsize_t> &)> &edit,
    const bool compress = false)
  {
    static_assert(
      std::is_same_v<T, double> || std::is_same_v<T, std::int64_t> ||
      std::is_same_v<T, std::int32_t> || std::is_same_v<T, std::uint8_t>);
    const hid_t type = std::is_same_v<T, double>       ? H5T_NATIVE_DOUBLE :
                       std::is_same_v<T, std::int64_t> ? H5T_NATIVE_INT64 :
                       std::is_same_v<T, std::int32_t> ? H5T_NATIVE_INT32 :
                                                         H5T_NATIVE_UINT8;
    std::filesystem::copy_file(
      original, copy, std::filesystem::copy_options::overwrite_existing);
    const hid_t file  = H5Fopen(copy.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    hid_t       set   = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    hid_t       space = H5Dget_space(set);
    std::vector<hsize_t> dims(H5Sget_simple_extent_ndims(space));
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    std::size_t n = 1;
    for (const hsize_t d : dims)
      n *= d;
    std::vector<T> values(n);
    H5Dread(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    H5Sclose(space);
    H5Dclose(set);
    edit(values, dims);
    H5Ldelete(file, name.c_str(), H5P_DEFAULT);
    space                = H5Screate_simple(dims.size(), dims.data(), nullptr);
    const hid_t creation = H5Pcreate(H5P_DATASET_CREATE);
    if (compress)
      {
        H5Pset_chunk(creation, dims.size(), dims.data());
        H5Pset_deflate(creation, 9);
      }
    set = H5Dcreate2(
      file, name.c_str(), type, space, H5P_DEFAULT, creation, H5P_DEFAULT);
    H5Pclose(creation);
    H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    H5Dclose(set);
    H5Sclose(space);
    H5Fclose(file);
  }

  /// The values of the dataset @p name of @p file (through a scratch copy).
  template <typename T>
  std::vector<T>
  dataset_values(const std::string &file, const std::string &name)
  {
    std::vector<T> result;
    edit_dataset<T>(file,
                    "scratch.h5",
                    name,
                    [&](std::vector<T> &values, std::vector<hsize_t> &) {
                      result = values;
                    });
    return result;
  }

  /// A copy of @p original named @p copy with the string attributes
  /// @p attributes (name, value) replaced.
  void
  edited_copy(
    const std::string                                      &original,
    const std::string                                      &copy,
    const std::vector<std::pair<std::string, std::string>> &attributes)
  {
    std::filesystem::copy_file(
      original, copy, std::filesystem::copy_options::overwrite_existing);
    const hid_t file = H5Fopen(copy.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    for (const auto &[name, value] : attributes)
      {
        H5Adelete(file, name.c_str());
        const hid_t type = H5Tcopy(H5T_C_S1);
        H5Tset_size(type, value.size());
        const hid_t space = H5Screate(H5S_SCALAR);
        const hid_t attribute =
          H5Acreate2(file, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
        H5Awrite(attribute, type, value.c_str());
        H5Aclose(attribute);
        H5Sclose(space);
        H5Tclose(type);
      }
    H5Fclose(file);
  }

  /// The bytes of the file @p name.
  std::string
  file_bytes(const std::string &name)
  {
    std::ifstream in(name, std::ios::binary);
    return {std::istreambuf_iterator<char>(in),
            std::istreambuf_iterator<char>()};
  }

  void
  expect_error(const std::string &what, const std::function<void()> &f)
  {
    try
      {
        f();
        std::cout << what << ": NO ERROR" << std::endl;
      }
    catch (ExceptionBase &e)
      {
        std::cout << what << ": " << message_of(e) << std::endl;
      }
  }
} // namespace

int
main()
{
  // HDF5 skips its file locks where this is FALSE, read once at its first
  // use: the case of a locked file needs them.
  unsetenv("HDF5_USE_FILE_LOCKING");
  // Start from a clean directory: earlier runs leave their database files
  // and journals here, and a complete one would not be built again.
  std::vector<std::filesystem::path> stale;
  for (const auto &file : std::filesystem::directory_iterator("."))
    if (file.path().filename().string().find(".h5") != std::string::npos)
      stale.push_back(file.path());
  for (const auto &file : stale)
    std::filesystem::remove(file);
  {
    std::cout << "Killed and resumed build" << std::endl;
    const pid_t child = fork();
    if (child == 0)
      {
        build(builder("killed.h5", true), palette());
        _exit(0);
      }
    // Kill the build once a few entries are in its journal.
    const std::string fingerprint =
      builder("killed.h5", true).settings(palette()).fingerprint();
    const std::size_t n_keys = CombinationIndex(2, true).size();
    while (Journal::read("killed.h5", fingerprint, n_keys, 1).size() < 20 &&
           !std::filesystem::exists("killed.h5") &&
           waitpid(child, nullptr, WNOHANG) == 0)
      usleep(1000);
    kill(child, SIGKILL);
    waitpid(child, nullptr, 0);
    const std::size_t journaled =
      Journal::read("killed.h5", fingerprint, n_keys, 1).size();
    std::cout << "killed before the end: " << std::boolalpha
              << !std::filesystem::exists("killed.h5")
              << ", at least 20 entries journaled: " << (journaled >= 20)
              << std::endl;
    // Another seed makes other entries: a build with it refuses the
    // journal, naming the difference and both ways on.
    expect_error("the journal opened with another seed", [] {
      std::ostringstream log;
      open(builder("killed.h5", true, "all", 1, 0, 1, 30, 1), palette(), log);
    });

    std::ostringstream    log;
    const DatabaseBuilder b = builder("killed.h5", true);
    Hierarchy             level2;
    Database              resumed = b.open(palette(), level2, log);
    std::cout << "entries recovered = journaled: "
              << (resumed.entries().size() == journaled) << std::endl;
    b.build(palette(), resumed, level2, nullptr, log, false);
    const Database full = build(builder("full.h5", true), palette());
    std::cout << "orbits of 2 materials + void: " << full.entries().size() + 1
              << std::endl;
    std::cout << "resumed build equals uninterrupted build: "
              << same_entries(Database::load("killed.h5"), full)
              << ", journal removed: "
              << !std::filesystem::exists("killed.h5.journal") << std::endl;
    // HDF5 records no modification times: equal contents, equal bytes.
    std::cout << "resumed file equals uninterrupted file byte for byte: "
              << (file_bytes("killed.h5") == file_bytes("full.h5"))
              << std::endl;
    // A build killed after its last fit, before its save: the file lacks
    // the journal's entries. A rerun with nothing left to fit saves them
    // and removes the journal.
    {
      Database unsaved(b.settings(palette()), 2);
      Journal  journal("unsaved.h5", fingerprint, n_keys, 1);
      for (unsigned int e = 0; e < full.entries().size(); ++e)
        if (e % 2 == 0)
          unsaved.add(full.entries()[e]);
        else
          journal.append(full.entries()[e]);
      unsaved.save("unsaved.h5");
    }
    build(builder("unsaved.h5", true), palette());
    std::cout << "rerun of a build killed before its save: file complete: "
              << same_entries(Database::load("unsaved.h5"), full)
              << ", journal removed: "
              << !std::filesystem::exists("unsaved.h5.journal") << std::endl;

    // A journal is read up to its first damaged record, also one whose
    // checksum holds: a key beyond the palette, a negative modulus or a
    // child fit's direction that is not a unit vector.
    for (const auto &[damage, spoil] :
         std::vector<std::pair<std::string, std::function<void(Entry &)>>>{
           {"key beyond the palette", [&](Entry &e) { e.key = n_keys; }},
           {"negative mu", [](Entry &e) { e.material.points[3].mu = -1; }},
           {"child direction not of unit length",
            [](Entry &e) { e.child_material.points[5].direction *= 2; }},
           {"median error above the largest",
            [](Entry &e) { e.median_error = e.max_error + 1; }},
           {"reversed strain range",
            [](Entry &e) { std::swap(e.min_strain, e.max_strain); }}})
      {
        std::filesystem::remove("forged.h5.journal");
        {
          Journal journal("forged.h5", fingerprint, n_keys, 1);
          Entry   bad = full.entries()[1];
          spoil(bad);
          journal.append(full.entries()[0]);
          journal.append(bad);
          journal.append(full.entries()[2]);
        }
        std::cout << "journal with a record of " << damage << ": records read "
                  << Journal::read("forged.h5", fingerprint, n_keys, 1).size()
                  << " of 3" << std::endl;
      }
    // So is one of level 2's shape, which the level-1 lookups would read
    // without its child points. Journal::append() writes only its own
    // level's shape: the record comes from a level-2 journal with the same
    // header, spliced between two level-1 records.
    {
      for (const std::string file : {"forged.h5", "level2_shape.h5"})
        std::filesystem::remove(file + ".journal");
      Journal("forged.h5", fingerprint, n_keys, 1).append(full.entries()[0]);
      Journal("forged.h5", fingerprint, n_keys, 1).append(full.entries()[2]);
      Entry level2_shape = full.entries()[1];
      level2_shape.material.points.resize(64, level2_shape.material.points[0]);
      level2_shape.child_material.points.clear();
      Journal("level2_shape.h5", fingerprint, n_keys, 2).append(level2_shape);
      const std::string level1 = testing::content_of("forged.h5.journal"),
                        level2 = testing::content_of("level2_shape.h5.journal");
      const std::size_t header = sizeof(std::uint64_t) + fingerprint.size(),
                        record = (level1.size() - header) / 2;
      std::ofstream("forged.h5.journal", std::ios::binary)
        << level1.substr(0, header + record) << level2.substr(header)
        << level1.substr(header + record);
      std::cout << "journal with a record of level 2's shape: records read "
                << Journal::read("forged.h5", fingerprint, n_keys, 1).size()
                << " of 3" << std::endl;
    }
    // A record of a combination that is not its orbit's representative
    // (damage a checksum cannot catch) is an error naming the journal.
    std::filesystem::remove("forged.h5.journal");
    {
      Journal           journal("forged.h5", fingerprint, n_keys, 1);
      Entry             image = full.entries()[1];
      const Combination c     = full.combinations().combination(image.key);
      for (unsigned int g = 0; image.key == full.entries()[1].key; ++g)
        image.key = full.combinations().key(full.symmetries().apply(g, c));
      journal.append(image);
    }
    expect_error("journal with a record of a combination that is not its "
                 "orbit's representative",
                 [&] { open(builder("forged.h5", true), palette(), log); });
    std::filesystem::remove("forged.h5.journal");
    std::filesystem::create_directory("forged.h5.journal");
    expect_error("journal that is a directory",
                 [&] { open(builder("forged.h5", true), palette(), log); });
    std::filesystem::remove("forged.h5.journal");
    // One that cannot be opened is not missing: the next Journal would cut
    // it to nothing.
    std::filesystem::create_symlink("forged.h5.journal", "forged.h5.journal");
    expect_error("journal that cannot be opened (a link to itself)",
                 [&] { open(builder("forged.h5", true), palette(), log); });
    std::filesystem::remove("forged.h5.journal");
    // A build killed while appending leaves a torn record; a resumed
    // build cuts it off, so the records it appends can be read.
    std::filesystem::remove("forged.h5.journal");
    {
      Journal journal("forged.h5", fingerprint, n_keys, 1);
      journal.append(full.entries()[0]);
      journal.append(full.entries()[1]);
    }
    {
      std::ofstream torn("forged.h5.journal", std::ios::binary | std::ios::app);
      const std::uint32_t magic  = 0x4444464dU;
      const double        key[2] = {double(full.entries()[2].key), 0.5};
      torn.write(reinterpret_cast<const char *>(&magic), sizeof(magic));
      torn.write(reinterpret_cast<const char *>(key), sizeof(key));
    }
    std::cout << "journal with a torn record: records read "
              << Journal::read("forged.h5", fingerprint, n_keys, 1).size()
              << " of 2";
    {
      Journal journal("forged.h5", fingerprint, n_keys, 1);
      journal.append(full.entries()[3]);
    }
    std::cout << ", after resuming and appending one: "
              << Journal::read("forged.h5", fingerprint, n_keys, 1).size()
              << " of 3" << std::endl;
    // A record that cannot be written stops the build (/dev/full fails
    // every write with ENOSPC).
    std::filesystem::remove("full_disk.h5.journal");
    std::filesystem::create_symlink("/dev/full", "full_disk.h5.journal");
    expect_error("journal on a full disk", [&] {
      Journal journal("full_disk.h5", fingerprint, n_keys, 1);
      journal.append(full.entries()[0]);
    });
    std::filesystem::remove("full_disk.h5.journal");
    // A record cut short by a file size limit is cut off, and the journal
    // takes no more records, also once the limit is raised: they would
    // follow the torn one, unread.
    {
      std::filesystem::remove("torn.h5.journal");
      Journal("torn.h5", fingerprint, n_keys, 1);
      const auto header = std::filesystem::file_size("torn.h5.journal");
      Journal("torn.h5", fingerprint, n_keys, 1).append(full.entries()[0]);
      const auto record =
        std::filesystem::file_size("torn.h5.journal") - header;
      std::cout.flush();
      const pid_t appender = fork();
      if (appender == 0)
        {
          std::signal(SIGXFSZ, SIG_IGN);
          // The limit holds for the test's output file too, which may be
          // longer: what the test prints meanwhile waits in memory.
          std::ostringstream    held;
          std::streambuf *const out = std::cout.rdbuf(held.rdbuf());
          rlimit limit = {rlim_t(header + record + record / 2), RLIM_INFINITY};
          setrlimit(RLIMIT_FSIZE, &limit);
          {
            Journal journal("torn.h5", fingerprint, n_keys, 1);
            expect_error("record beyond a file size limit",
                         [&] { journal.append(full.entries()[1]); });
            limit.rlim_cur = RLIM_INFINITY;
            setrlimit(RLIMIT_FSIZE, &limit);
            std::cout.rdbuf(out);
            std::cout << held.str();
            expect_error("record after the failed one",
                         [&] { journal.append(full.entries()[2]); });
          }
          std::cout.flush();
          _exit(0);
        }
      waitpid(appender, nullptr, 0);
      std::cout << "then: records read "
                << Journal::read("torn.h5", fingerprint, n_keys, 1).size()
                << ", the journal ends with its last complete record: "
                << (std::filesystem::file_size("torn.h5.journal") ==
                    header + record)
                << std::endl;
    }
    // A new journal's header is written under another name first; if that
    // fails, the partial file goes too.
    std::filesystem::remove("full_disk.h5.journal.partial");
    std::filesystem::create_symlink("/dev/full",
                                    "full_disk.h5.journal.partial");
    expect_error("new journal on a full disk", [&] {
      Journal journal("full_disk.h5", fingerprint, n_keys, 1);
    });
    std::cout << "partial header removed: "
              << !std::filesystem::is_symlink("full_disk.h5.journal.partial")
              << ", no journal: "
              << !std::filesystem::exists("full_disk.h5.journal") << std::endl;
    // A database file that cannot be written whole (a file size limit
    // stands in for a full disk) is an error that leaves the old file
    // and no partial one.
    std::filesystem::copy_file(
      "full.h5",
      "limited.h5",
      std::filesystem::copy_options::overwrite_existing);
    std::cout.flush();
    const pid_t writer = fork();
    if (writer == 0)
      {
        std::signal(SIGXFSZ, SIG_IGN);
        const rlimit limit = {4096, 4096};
        setrlimit(RLIMIT_FSIZE, &limit);
        expect_error("database file beyond a file size limit",
                     [&] { full.save("limited.h5"); });
        std::cout.flush();
        _exit(0);
      }
    waitpid(writer, nullptr, 0);
    std::cout << "old file kept: "
              << same_entries(Database::load("limited.h5"), full)
              << ", no partial file: "
              << !std::filesystem::exists("limited.h5.partial") << std::endl;
    for (const unsigned int threads : {2u, 3u})
      std::cout << threads << " threads give the same entries: "
                << same_entries(build(builder("threads" +
                                                std::to_string(threads) + ".h5",
                                              true,
                                              "all",
                                              threads),
                                      palette()),
                                full)
                << std::endl;

    // Another seed draws other samples: other entries, in a file that the
    // settings of seed 0 do not open.
    std::cout
      << "seed 1 gives other entries: "
      << !same_entries(build(builder("seed1.h5", true, "all", 1, 0, 1, 30, 1),
                             palette()),
                       full)
      << std::endl;
    expect_error("the file of seed 1 opened with seed 0", [&]() {
      std::ostringstream log;
      open(builder("seed1.h5", true), palette(), log);
    });
  }

  {
    std::cout << "Symmetry" << std::endl;
    const CubeSymmetries  group;
    std::set<Combination> orbits3, orbits4;
    for (std::size_t key = 0; key < 6561; ++key)
      orbits3.insert(
        group.canonical(CombinationIndex(3, false).combination(key)).first);
    for (std::size_t key = 0; key < 65536; ++key)
      orbits4.insert(
        group.canonical(CombinationIndex(3, true).combination(key)).first);
    std::cout << "orbits of 3 materials: " << orbits3.size()
              << ", of 3 materials + void: " << orbits4.size() << std::endl;
    bool group_ok = true;
    for (unsigned int g = 0; g < CubeSymmetries::size; ++g)
      {
        const Tensor<2, 3> &R = group.matrix(g);
        group_ok &=
          ((R * transpose(R) - unit_symmetric_tensor<3>()).norm() < 1e-14);
        const Combination c = {{1, 2, 3, 4, 5, 6, 7, 8}};
        group_ok &= (group.apply(group.inverse(g), group.apply(g, c)) == c);
        const auto canonical = group.canonical(group.apply(g, c));
        group_ok &=
          (group.apply(canonical.second, canonical.first) == group.apply(g, c));
      }
    std::cout << "48 orthogonal maps with inverses: " << group_ok << std::endl;
    // The octant permutation is the matrix acting on the octants' centres
    // (relative to the block's centre), so points and directions turn
    // together.
    bool permutation_ok = true;
    for (unsigned int g = 0; g < CubeSymmetries::size; ++g)
      for (unsigned int k = 0; k < 8; ++k)
        {
          const auto centre = [](const unsigned int octant) {
            return Tensor<1, 3>({(octant & 1) - 0.5,
                                 ((octant >> 1) & 1) - 0.5,
                                 ((octant >> 2) & 1) - 0.5});
          };
          permutation_ok &=
            ((group.matrix(g) * centre(k) - centre(group.image(g, k))).norm() <
             1e-14);
        }
    std::cout << "octant permutations follow the matrices: " << permutation_ok
              << std::endl;

    // A rotated copy fitted directly agrees with the mapped fit.
    const scene::Palette p3 =
      palette("E=1e5 nu=0.45; E=1e6 nu=0.45; E=1e7 nu=0.45");
    const Database      db(builder("unused.h5", true).settings(p3), 3);
    const CoarseElement element(1);
    SamplingSettings    sampling;
    sampling.n_directions = 100;
    // Force patterns, although the block is mixed: the corners of
    // embedded samples move affinely, and an affine motion tells the
    // points apart by their springs alone (the unmapped fit came within
    // 3.5 times the seed-to-seed difference).
    sampling.embedded        = 0;
    const Combination  c     = {{1, 3, 0, 2, 3, 1, 1, 2}};
    const unsigned int g     = 13;
    const Combination  image = group.apply(g, c);
    const auto         fit   = [&](const Combination  &combination,
                         const std::uint64_t seed) {
      return DatabaseBuilder::fit_entry(
               p3, db, combination, sampling, FitSettings(), element, seed)
        .material;
    };
    const Metamaterial mapped   = transform(fit(c, 1), group, g);
    const Metamaterial direct   = fit(image, 2);
    const Metamaterial reseeded = fit(image, 3);
    const Metamaterial other    = fit({{3, 1, 2, 0, 1, 3, 3, 2}}, 2);
    // Fresh samples of the rotated block: the mapped fit predicts their
    // fine energies as well as the direct fits do.
    std::array<std::vector<material::MaterialPoint>, 8> children;
    for (unsigned int k = 0; k < 8; ++k)
      if (image[k] != 0)
        children[k].assign(8, p3[image[k]].material_point());
    unsigned int dropped;
    const auto   fresh = BlockSampler(children).sample(sampling, 99, dropped);
    const auto   median_error = [&](const Metamaterial &m) {
      std::vector<double> e = relative_energy_errors(element, m, fresh);
      std::sort(e.begin(), e.end());
      return e[e.size() / 2];
    };
    // The fits as energy functions: the median over the fresh samples of
    // |E_a - E_b| / E_s. Three seeds give three independent fits of the
    // rotated block if the mapping is right, so the mapped fit must differ
    // from each direct fit about as much as the two differ from each other
    // (the sampling noise); the unmapped fit (the rotation forgotten) must
    // not. Their spring directions come from the same stretch test, turned.
    const auto difference = [&](const Metamaterial &a, const Metamaterial &b) {
      std::vector<double> d;
      for (const Sample &sample : fresh)
        {
          double energy_a, energy_b;
          if (element.energy(sample.corners, a, energy_a) &&
              element.energy(sample.corners, b, energy_b))
            d.push_back(std::abs(energy_a - energy_b) / sample.energy);
        }
      std::sort(d.begin(), d.end());
      return d[d.size() / 2];
    };
    double largest_angle = 0;
    for (unsigned int k = 0; k < 8; ++k)
      largest_angle =
        testing::worst(largest_angle,
                       std::acos(
                         std::min(1.,
                                  std::abs(mapped.points[k].direction *
                                           direct.points[k].direction))));
    const double noise       = difference(direct, reseeded);
    const double to_direct   = difference(mapped, direct),
                 to_reseeded = difference(mapped, reseeded),
                 unmapped    = difference(fit(c, 1), direct);
    const auto precision     = std::cout.precision(2);
    std::cout << "energies of the rotated block's fits on fresh samples: "
                 "the direct fits differ by "
              << noise << ", the mapped fit from them by " << to_direct
              << " and " << to_reseeded << ", the unmapped fit by " << unmapped
              << "; mapped within 1.5x the seed-to-seed difference: "
              << (testing::worst(to_direct, to_reseeded) < 1.5 * noise)
              << ", unmapped fit beyond 5x: " << (unmapped > 5 * noise)
              << ", spring directions within 2 degrees: "
              << (largest_angle < 2 * numbers::PI / 180) << std::endl;
    std::cout.precision(precision);
    const double e_mapped   = median_error(mapped),
                 e_direct   = median_error(direct),
                 e_reseeded = median_error(reseeded),
                 e_other    = median_error(other);
    std::cout << "median error on fresh samples of the rotated block: mapped "
                 "fit within 25% of the direct fits: "
              << (std::abs(e_mapped - 0.5 * (e_direct + e_reseeded)) <
                  0.25 * std::max(e_direct, e_reseeded))
              << ", another combination's fit at least twice as large: "
              << (e_other > 2 * std::max(e_direct, e_reseeded)) << std::endl;
  }

  {
    std::cout << "Farthest point sampling" << std::endl;
    const std::vector<std::vector<double>> points = {
      {0}, {1}, {2}, {10}, {11}, {5}};
    for (const unsigned int i : farthest_point_sampling(points, 4, {0}))
      std::cout << i << " ";
    std::cout << std::endl;
    // Required points are representatives of their own, and sampling goes
    // on from them; more required points than representatives are sampled
    // among themselves.
    for (const std::vector<unsigned int> &required :
         {std::vector<unsigned int>{1, 4}, std::vector<unsigned int>{0, 1, 2}})
      {
        const Clustering c =
          cluster(points, 2 + (required.size() == 2), 1, required);
        std::cout << "required";
        for (const unsigned int p : required)
          std::cout << " " << p;
        std::cout << ": representatives";
        for (const unsigned int p : c.representatives)
          std::cout << " " << p;
        std::cout << ", nearest";
        for (const unsigned int r : c.nearest)
          std::cout << " " << c.representatives[r];
        std::cout << std::endl;
      }
    // Points that coincide are picked once: sampling stops when every point
    // coincides with a picked one, short of the number asked for.
    const std::vector<std::vector<double>> repeated = {{0}, {3}, {0}, {3}, {3}};
    std::cout << "5 points with 2 distinct values, 4 asked for: picked";
    for (const unsigned int i : farthest_point_sampling(repeated, 4, {0}))
      std::cout << " " << i;
    const Clustering c = cluster(repeated, 4, 1);
    std::cout << "; clustered: " << c.representatives.size()
              << " representatives, nearest";
    for (const unsigned int r : c.nearest)
      std::cout << " " << c.representatives[r];
    std::cout << std::endl;
  }

  {
    std::cout << "Round trip, lookups, compression" << std::endl;
    const Database db     = build(builder("small.h5", false), palette());
    const Database loaded = Database::load("small.h5");
    std::cout << "entries: " << db.entries().size()
              << ", loaded equal: " << same_entries(db, loaded) << std::endl;
    // The lookup of a combination's image is the image of its lookup. A
    // block split in two layers has the mirror symmetries of its layers,
    // which its laminate springs do not have (laminate_springs()): there
    // the two may differ in their spring lines, but not in their energy
    // under a homogeneous deformation.
    bool                  lookups_ok = true, laminates_ok = true;
    unsigned int          n_laminates = 0;
    const CubeSymmetries &group       = loaded.symmetries();
    const CoarseElement   element(1);
    CornerDisplacements   homogeneous;
    for (unsigned int v = 0; v < 8; ++v)
      homogeneous[v] = Tensor<1, 3>({0.1 * (v & 1) + 0.05 * ((v >> 2) & 1),
                                     -0.03 * ((v >> 1) & 1),
                                     0.02 * (v & 1) + 0.04 * ((v >> 1) & 1)});
    for (const auto &c : DatabaseBuilder::all_combinations(db))
      {
        const bool split = split_axis(c).has_value();
        n_laminates += split;
        for (unsigned int g = 0; g < CubeSymmetries::size; ++g)
          {
            const Metamaterial a = loaded.lookup(group.apply(g, c));
            const Metamaterial b = transform(loaded.lookup(c), group, g);
            for (unsigned int k = 0; k < 8; ++k)
              lookups_ok &=
                (std::abs(a.points[k].mu - b.points[k].mu) <=
                   1e-12 * b.points[k].mu &&
                 std::abs(a.points[k].lambda - b.points[k].lambda) <=
                   1e-12 * b.points[k].lambda &&
                 std::abs(a.points[k].anisotropy - b.points[k].anisotropy) <=
                   1e-12 * b.points[k].mu &&
                 (b.points[k].anisotropy == 0 || split ||
                  std::abs(
                    std::abs(a.points[k].direction * b.points[k].direction) -
                    1) < 1e-8));
            if (split)
              {
                double energy_a, energy_b;
                element.energy(homogeneous, a, energy_a);
                element.energy(homogeneous, b, energy_b);
                laminates_ok &=
                  std::abs(energy_a - energy_b) <= 1e-12 * energy_b;
              }
          }
      }
    std::cout << "lookups commute with the 48 symmetries (mu, lambda, C, "
                 "spring directions up to sign except in blocks split in "
                 "two layers): "
              << lookups_ok << std::endl;
    std::cout << "blocks split in two layers: " << n_laminates
              << ", their lookups' energies under a homogeneous deformation "
                 "commute with the symmetries: "
              << laminates_ok << std::endl;

    // An entry's child fit is the fit of the same samples with the child
    // weight.
    SamplingSettings sampling;
    sampling.n_directions         = 30;
    sampling.n_magnitudes         = 2;
    sampling.n_stretch_directions = 20;
    FitSettings child_weight;
    child_weight.regularization = child_weight.child_regularization;
    const Combination mixed     = {{1, 2, 2, 1, 1, 1, 2, 1}};
    const Combination canonical = db.symmetries().canonical(mixed).first;
    const auto        fit       = [&](const FitSettings &fitting) {
      return DatabaseBuilder::fit_entry(
        palette(), db, canonical, sampling, fitting, CoarseElement(1), 11);
    };
    const Entry paper = fit(FitSettings()), direct = fit(child_weight);
    std::cout << "child fit = fit with Fitting/Child regularization: "
              << same_points(paper.child_material, direct.material)
              << ", differs from the coarse fit: "
              << !same_points(paper.child_material, paper.material)
              << std::endl;

    // The child fit is made for the Gauss rule's points whatever the coarse
    // element's offset; the coarse fit follows the offset. A block with
    // void takes force patterns, whose directions depend on the points.
    DatabaseSettings with_void;
    with_void.palette = DatabaseSettings::describe(palette());
    const Database void_db(with_void, palette().size());
    for (const Combination &c :
         {canonical,
          void_db.symmetries()
            .canonical(Combination{{1, 0, 2, 1, 1, 1, 2, 1}})
            .first})
      {
        const auto at = [&](const double offset) {
          return DatabaseBuilder::fit_entry(palette(),
                                            void_db,
                                            c,
                                            sampling,
                                            FitSettings(),
                                            CoarseElement(1, offset),
                                            11);
        };
        const Entry gauss = at(solver::gauss_point_offset), other = at(0.45);
        std::cout << "fits for the offset 0.45: child fit equals the Gauss "
                     "rule's: "
                  << same_points(other.child_material, gauss.child_material)
                  << ", coarse fit differs: "
                  << !same_points(other.material, gauss.material) << std::endl;
      }
    DatabaseSettings offset_settings = with_void;
    offset_settings.point_offset     = 0.45;
    std::cout << "fingerprint names the child fits' offset where the coarse "
                 "offset differs: "
              << (offset_settings.fingerprint().find(
                    "child fits at the Gauss rule") != std::string::npos)
              << ", and not where it does not: "
              << (with_void.fingerprint().find("child fits") ==
                  std::string::npos)
              << std::endl;

    Database compressed = loaded;
    compressed.compress(5, element, compression_deformations());
    // A symmetry permutes the points: the sorted shear moduli of a lookup
    // name its representative.
    std::set<std::vector<double>> distinct;
    for (const auto &c : DatabaseBuilder::all_combinations(compressed))
      {
        std::vector<double> mu;
        for (const auto &p : compressed.lookup(c).points)
          mu.push_back(p.mu);
        std::sort(mu.begin(), mu.end());
        distinct.insert(mu);
      }
    std::cout << "compressed to " << compressed.n_representatives()
              << " representatives, " << compressed.entries().size()
              << " entries kept, the combinations map to " << distinct.size()
              << " distinct metamaterials" << std::endl;
    compressed.save("compressed.h5");
    std::cout << "compressed round trip: "
              << same_entries(compressed, Database::load("compressed.h5"))
              << std::endl;
    {
      // A save replaces the file by a new one, which keeps the mode of the
      // old: 604, which no common umask gives a new file.
      namespace fs = std::filesystem;
      const fs::perms mode =
        fs::perms::owner_read | fs::perms::owner_write | fs::perms::others_read;
      fs::permissions("compressed.h5", mode);
      compressed.save("compressed.h5");
      std::cout << "saved over a file of mode 604: mode " << std::oct
                << static_cast<unsigned int>(
                     fs::status("compressed.h5").permissions() &
                     fs::perms::mask)
                << std::dec << std::endl;
    }
    // A build asking for another compression of a compressed file.
    std::cout << "the same compression builds: "
              << build(builder("compressed.h5", false, "all", 1, 5), palette())
                   .n_representatives()
              << " representatives" << std::endl;
    expect_error("another compression", [] {
      build(builder("compressed.h5", false, "all", 1, 3), palette());
    });
    {
      // Damage to a compressed file's lookup table that stays in range: a
      // symmetry that maps the entry's block onto neither the combination
      // nor a representative, at a combination that is a representative
      // and at one that is not.
      const auto symmetry =
        dataset_values<std::uint8_t>("compressed.h5", "lookup/symmetry");
      const auto position =
        dataset_values<std::int32_t>("compressed.h5", "lookup/entry");
      const Database file  = Database::load("compressed.h5");
      const auto    &index = file.combinations();
      const auto    &group = file.symmetries();
      // The combination the symmetry g maps the entry of k onto.
      const auto image = [&](const std::size_t k, const unsigned int g) {
        return index.key(
          group.apply(g, index.combination(file.entries()[position[k]].key)));
      };
      std::set<std::size_t> representatives;
      for (std::size_t k = 0; k < index.size(); ++k)
        if (position[k] >= 0 && image(k, symmetry[k]) == k)
          representatives.insert(k);
      std::cout << "compressed file: " << representatives.size()
                << " representatives in its lookup table" << std::endl;
      for (const bool representative : {true, false})
        {
          // A symmetry of combination k that maps its entry elsewhere,
          // onto no representative; CubeSymmetries::size if none does.
          const auto wrong_symmetry = [&](const std::size_t k) {
            unsigned int g = 0;
            while (g < CubeSymmetries::size &&
                   (image(k, g) == image(k, symmetry[k]) ||
                    representatives.count(image(k, g)) > 0))
              ++g;
            return g;
          };
          // The first such combination that has one.
          std::size_t k = 0;
          while (position[k] < 0 ||
                 (representatives.count(k) > 0) != representative ||
                 wrong_symmetry(k) == CubeSymmetries::size)
            ++k;
          const unsigned int wrong = wrong_symmetry(k);
          edit_dataset<std::uint8_t>("compressed.h5",
                                     "compressed_wrong_symmetry.h5",
                                     "lookup/symmetry",
                                     [&](std::vector<std::uint8_t> &values,
                                         std::vector<hsize_t> &) {
                                       values[k] = wrong;
                                     });
          expect_error(std::string("compressed table with a wrong symmetry "
                                   "at a ") +
                         (representative ? "representative" :
                                           "combination it represents") +
                         ", " + std::to_string(k),
                       [] { Database::load("compressed_wrong_symmetry.h5"); });
        }
      // A combination of a compressed file left without its entry, one
      // that is not a representative (whose entry others still use): a
      // compressed file was complete and takes no new entries.
      std::size_t hole = 0;
      while (position[hole] < 0 || representatives.count(hole) > 0)
        ++hole;
      edit_dataset<std::int32_t>("compressed.h5",
                                 "compressed_hole.h5",
                                 "lookup/entry",
                                 [&](std::vector<std::int32_t> &values,
                                     std::vector<hsize_t> &) {
                                   values[hole] = -1;
                                 });
      expect_error("compressed table without an entry at " +
                     std::to_string(hole),
                   [] { Database::load("compressed_hole.h5"); });
    }
    // More representatives asked for than combinations have distinct
    // features: all are kept, and the file builds again with the setting.
    std::filesystem::copy_file("small.h5", "compressed_all.h5");
    build(builder("compressed_all.h5", false, "all", 1, 1000), palette());
    std::cout << "compressed with 1000 representatives, built again: "
              << build(builder("compressed_all.h5", false, "all", 1, 1000),
                       palette())
                   .entries()
                   .size()
              << " entries kept" << std::endl;

    // Lazy mode: only the scene's blocks.
    scene::VoxelGrid grid({{4, 2, 2}}, 0.01, 1);
    grid(0, 0, 0) = 2;
    grid(3, 1, 1) = 2;
    std::filesystem::remove("lazy.h5");
    std::ostringstream    log;
    const DatabaseBuilder lazy = builder("lazy.h5", false, "scene");
    Hierarchy             level2;
    Database              ldb = lazy.open(palette(), level2, log);
    const std::vector<scene::VoxelGrid> grids = {grid};
    lazy.build(palette(), ldb, level2, &grids, log, false);
    Database again = open(lazy, palette(), log);
    std::cout << "lazy build fitted "
              << Database::load("lazy.h5").entries().size()
              << " entries, a second run has "
              << again.missing(DatabaseBuilder::scene_combinations(grid)).size()
              << " to fit" << std::endl;
    // Through a link to a shared file, a lazy build adds its entries to
    // that file and keeps the link (a save once replaced the link with a
    // file of its own).
    {
      std::filesystem::remove_all("shared");
      std::filesystem::create_directory("shared");
      std::filesystem::copy_file("lazy.h5", "shared/lazy.h5");
      std::filesystem::remove("link.h5");
      std::filesystem::create_symlink("shared/lazy.h5", "link.h5");
      scene::VoxelGrid edited      = grid;
      edited(1, 0, 0)              = 2;
      const DatabaseBuilder linked = builder("link.h5", false, "scene");
      Hierarchy             level2;
      Database              shared = linked.open(palette(), level2, log);
      const std::vector<scene::VoxelGrid> edited_grids = {edited};
      linked.build(palette(), shared, level2, &edited_grids, log, false);
      // A link made before the shared file's first build dangles; the
      // build creates the file it names.
      std::filesystem::remove("link_first.h5");
      std::filesystem::create_symlink("shared/first.h5", "link_first.h5");
      const DatabaseBuilder first = builder("link_first.h5", false, "scene");
      Hierarchy             fresh_level2;
      Database              fresh = first.open(palette(), fresh_level2, log);
      first.build(palette(), fresh, fresh_level2, &edited_grids, log, false);
      std::cout << "  through a dangling link: still a link "
                << std::filesystem::is_symlink("link_first.h5")
                << ", the file it names has "
                << Database::load("shared/first.h5").entries().size()
                << " entries" << std::endl;
      std::cout << "  through a link: still a link "
                << std::filesystem::is_symlink("link.h5")
                << ", the shared file gained "
                << Database::load("shared/lazy.h5").entries().size() -
                     Database::load("lazy.h5").entries().size()
                << " entries" << std::endl;
    }

    // An all-void block gets no element, so a database without void need
    // not cover it.
    scene::VoxelGrid holed({{4, 2, 2}}, 0.01, 2);
    for (unsigned int i = 2; i < 4; ++i)
      for (unsigned int j = 0; j < 2; ++j)
        for (unsigned int k = 0; k < 2; ++k)
          holed(i, j, k) = 0;
    std::cout
      << "a scene with an all-void block, without void in the database: "
      << again.missing(DatabaseBuilder::scene_combinations(holed)).size()
      << " to fit" << std::endl;
  }

  {
    std::cout << "Second level" << std::endl;
    std::filesystem::remove("level2.h5");
    std::ostringstream    log;
    const DatabaseBuilder b = builder("level2.h5", false, "all", 2, 0, 2);
    Hierarchy             built;
    Database              db = b.open(palette(), built, log);
    b.build(palette(), db, built, nullptr, log, false);
    Hierarchy      level2;
    const Database loaded = Database::load("level2.h5", &level2);
    std::cout << "representatives: " << level2.n_representatives()
              << ", fitted: " << level2.entries.size() << std::endl;
    // A level-2 build killed after its last fit, before its save: a rerun
    // with nothing left to fit saves the journaled fits and removes the
    // journal.
    {
      Hierarchy unsaved = level2;
      Journal   journal("level2_unsaved.h5.level2",
                      loaded.fingerprint() + " | " +
                        level2.settings.fingerprint(),
                      level2.n_representatives(),
                      2);
      unsaved.entries.clear();
      for (unsigned int e = 0; e < level2.entries.size(); ++e)
        if (e % 2 == 0)
          unsaved.entries.push_back(level2.entries[e]);
        else
          journal.append(level2.entries[e]);
      loaded.save("level2_unsaved.h5", &unsaved);
    }
    build(builder("level2_unsaved.h5", false, "all", 2, 0, 2), palette());
    Hierarchy rerun;
    Database::load("level2_unsaved.h5", &rerun);
    std::cout << "rerun of a level-2 build killed before its save: file "
                 "complete: "
              << same_level2_entries(rerun.entries, level2.entries)
              << ", journal removed: "
              << !std::filesystem::exists("level2_unsaved.h5.level2.journal")
              << std::endl;

    // Every 4x4x4 block of a random grid finds a 64-point metamaterial
    // whose points are physical (the file's validation checks it too).
    scene::VoxelGrid grid({{8, 8, 4}}, 0.01, 1);
    std::mt19937     generator(5);
    for (std::size_t v = 0; v < grid.n_voxels(); ++v)
      grid[v] = 1 + generator() % 2;
    bool all_found = true;
    for (const auto &blocks : DatabaseBuilder::scene_blocks(grid))
      {
        const Metamaterial m = level2.lookup(loaded, blocks);
        all_found &= (m.points.size() == 64);
        for (const auto &p : m.points)
          all_found &= (p.mu > 0 && p.lambda >= 0 && p.anisotropy >= 0);
      }
    std::cout << "every block of a random grid has a 64-point metamaterial: "
              << all_found << std::endl;
    // A scene built on this complete file fits nothing: its blocks take
    // their nearest representatives, and the file keeps its fits (it used
    // to build its tables anew around the scene's blocks, dropping them).
    {
      std::filesystem::copy_file(
        "level2.h5",
        "level2_scene.h5",
        std::filesystem::copy_options::overwrite_existing);
      Hierarchy                           scene_level2;
      const std::vector<scene::VoxelGrid> grids = {grid};
      const Database                      scene_db =
        build_levels("level2_scene.h5", "scene", &grids, &scene_level2);
      Hierarchy reread;
      Database::load("level2_scene.h5", &reread);
      std::cout << "a scene built on the complete file: its level-2 fits "
                   "kept: "
                << same_level2_entries(reread.entries, level2.entries)
                << ", the scene's lookups equal the file's: "
                << (scene_level2
                      .lookup(scene_db, DatabaseBuilder::scene_blocks(grid)[0])
                      .points[5]
                      .mu ==
                    level2
                      .lookup(loaded, DatabaseBuilder::scene_blocks(grid)[0])
                      .points[5]
                      .mu)
                << std::endl;
    }

    // A level-2 build with @p setting on a copy of @p file prints its
    // "Level 2:" lines.
    const auto build_level2 = [](const std::string &file,
                                 const std::string &setting) {
      std::filesystem::copy_file(
        file,
        "level2_settings.h5",
        std::filesystem::copy_options::overwrite_existing);
      std::ostringstream    log;
      const DatabaseBuilder b =
        builder("level2_settings.h5",
                false,
                "all",
                1,
                0,
                2,
                30,
                0,
                "subsection Database\n  subsection Level 2\n    set " +
                  setting + "\n  end\nend\n");
      Hierarchy renewed;
      Database  db = b.open(palette(), renewed, log);
      b.build(palette(), db, renewed, nullptr, log, false);
      std::cout << file << " with Level 2/" << setting << ":" << std::endl;
      std::istringstream lines(log.str());
      for (std::string line; std::getline(lines, line);)
        if (line.rfind("Level 2:", 0) == 0)
          std::cout << "  " << line << std::endl;
    };
    // Other budgets renew the tables and keep the fits of compositions
    // that are still representatives; another level-2 weight drops the
    // file's fits, and the build says so.
    for (const std::string setting :
         {"Representatives = 12", "Regularization = 0.5"})
      build_level2("level2.h5", setting);

    // Compressing level 1 drops the level 2 sampled from it, and the build
    // says so; with Levels = 1 the file is saved without it.
    {
      std::filesystem::copy_file(
        "level2.h5",
        "level2_compressed.h5",
        std::filesystem::copy_options::overwrite_existing);
      std::ostringstream    log;
      const DatabaseBuilder b =
        builder("level2_compressed.h5", false, "all", 1, 5, 1);
      Hierarchy kept;
      Database  db = b.open(palette(), kept, log);
      b.build(palette(), db, kept, nullptr, log, false);
      std::istringstream lines(log.str());
      for (std::string line; std::getline(lines, line);)
        if (line.rfind("Compressed to", 0) == 0 ||
            line.rfind("Level 2 (", 0) == 0)
          std::cout << line << std::endl;
      Hierarchy saved;
      Database::load("level2_compressed.h5", &saved);
      std::cout << "compressed file holds a level 2: " << !saved.empty()
                << std::endl;
    }

    // The second level's point offset and sampler version: named in its
    // settings. Files written before either had one of its own name none;
    // their second level is the Gauss rule's where the first level has the
    // default offset, and is dropped otherwise (0.45 in the edited copy).
    // Files that name just the offset are of sampler version 1 (which read
    // a corner over a void voxel from its node, and fitted blocks with
    // partly void children far too soft). A level-2 build drops the fits
    // of version 1 and says so.
    const std::string settings = level2.settings.fingerprint();
    std::cout << "level-2 settings: " << settings << std::endl;
    edited_copy("level2.h5",
                "level2_unnamed.h5",
                {{"level 2 settings",
                  settings.substr(0, settings.rfind(", point offset: "))}});
    {
      // The first level's offset is stored twice too.
      std::string       level1 = Database::load("level2.h5").fingerprint();
      const std::string named  = " | coarse point offset: ";
      const std::size_t at     = level1.find(named) + named.size();
      level1.replace(at, level1.find_first_of(", ", at) - at, "0.45");
      edited_copy("level2.h5",
                  "level2_unnamed_045.h5",
                  {{"level 2 settings",
                    settings.substr(0, settings.rfind(", point offset: "))},
                   {"coarse point offset", "0.45"},
                   {"settings", level1}});
    }
    edited_copy("level2.h5",
                "level2_version_1.h5",
                {{"level 2 settings",
                  settings.substr(0, settings.rfind(", sampler version: "))}});
    HierarchySettings other = level2.settings;
    other.point_offset      = 0.45;
    edited_copy("level2.h5",
                "level2_045.h5",
                {{"level 2 settings", other.fingerprint()}});
    for (const std::string file : {"level2_unnamed.h5",
                                   "level2_unnamed_045.h5",
                                   "level2_version_1.h5",
                                   "level2_045.h5"})
      {
        Hierarchy read;
        Database::load(file, &read);
        std::cout << file << ": ";
        if (read.empty())
          std::cout << "level 2 dropped" << std::endl;
        else
          std::cout << "level-2 point offset " << read.settings.point_offset
                    << ", sampler version " << read.settings.sampler_version
                    << ", entries kept: "
                    << same_level2_entries(read.entries, level2.entries)
                    << std::endl;
      }
    build_level2("level2_version_1.h5", "Regularization = 1");
    other.point_offset = 0.2;
    edited_copy("level2.h5",
                "level2_bad_offset.h5",
                {{"level 2 settings", other.fingerprint()}});
    expect_error("level-2 point offset 0.2", [] {
      Hierarchy read;
      Database::load("level2_bad_offset.h5", &read);
    });
    other.point_offset    = level2.settings.point_offset;
    other.sampler_version = 3;
    edited_copy("level2.h5",
                "level2_version_3.h5",
                {{"level 2 settings", other.fingerprint()}});
    expect_error("level-2 sampler version 3", [] {
      Hierarchy read;
      Database::load("level2_version_3.h5", &read);
    });
  }

  {
    // Lazy mode at level 2: each block of a scene is the representative of
    // itself, so it is fitted as it is. A second scene renews the tables
    // but keeps the first scene's fits, and the fits equal those of one
    // build for both scenes.
    std::cout << "Second level, lazy" << std::endl;
    // Random 2x2x2 sub-blocks of three kinds (soft, stiff, checkerboard),
    // so that the scenes' parts fit into the test's small budgets.
    const auto random_grid = [](const unsigned int seed) {
      scene::VoxelGrid grid({{8, 4, 4}}, 0.01, 1);
      std::mt19937     generator(seed);
      for (unsigned int k = 0; k < 4; k += 2)
        for (unsigned int j = 0; j < 4; j += 2)
          for (unsigned int i = 0; i < 8; i += 2)
            {
              const unsigned int kind = generator() % 3;
              for (unsigned int v = 0; v < 8; ++v)
                grid(i + (v & 1), j + ((v >> 1) & 1), k + (v >> 2)) =
                  kind < 2 ? 1 + kind : 1 + ((v ^ (v >> 1) ^ (v >> 2)) & 1);
            }
      return grid;
    };
    const std::vector<scene::VoxelGrid> first  = {random_grid(1)},
                                        second = {random_grid(2)},
                                        both   = {first[0], second[0]};
    // The level-2 metamaterial of every block of @p grids, built into @p file.
    const auto build_lazily = [](const std::string                   &file,
                                 const std::vector<scene::VoxelGrid> &grids,
                                 const bool with_void = false) {
      std::ostringstream    log;
      const DatabaseBuilder b = builder(file, with_void, "scene", 1, 0, 2);
      Hierarchy             level2;
      Database              db = b.open(palette(), level2, log);
      b.build(palette(), db, level2, &grids, log, false);
      std::vector<Metamaterial> result;
      bool                      exact = true;
      for (const auto &grid : grids)
        for (const auto &block : DatabaseBuilder::scene_blocks(grid))
          {
            const int r = level2.find(db, block);
            exact &= (level2.composition(db, r) == block);
            result.push_back(level2.lookup(db, block));
          }
      std::cout << "  " << level2.n_representatives() << " representatives, "
                << level2.entries.size() << " fitted, every block its own "
                << "representative: " << exact << std::endl;
      return result;
    };
    const auto same = [](const std::vector<Metamaterial> &a,
                         const std::vector<Metamaterial> &b) {
      bool equal = (a.size() == b.size());
      for (unsigned int m = 0; equal && m < a.size(); ++m)
        for (unsigned int q = 0; q < 64; ++q)
          equal &= (a[m].points[q].mu == b[m].points[q].mu &&
                    a[m].points[q].lambda == b[m].points[q].lambda &&
                    a[m].points[q].anisotropy == b[m].points[q].anisotropy);
      return equal;
    };
    std::filesystem::remove("lazy2.h5");
    std::filesystem::remove("lazy2_both.h5");
    const auto first_alone = build_lazily("lazy2.h5", first);
    std::filesystem::copy_file("lazy2.h5", "lazy2_killed.h5");
    build_lazily("lazy2.h5", second);
    const auto first_again = build_lazily("lazy2.h5", first);
    const auto together    = build_lazily("lazy2_both.h5", both);
    // A build of the first scene killed after its level-2 fits, before its
    // save: they are only in the journal. The second scene renews the
    // tables, keeps those fits and saves them with its own.
    {
      Hierarchy      unsaved;
      const Database db = Database::load("lazy2_killed.h5", &unsaved);
      {
        Journal journal("lazy2_killed.h5.level2",
                        db.fingerprint() + " | " +
                          unsaved.settings.fingerprint(),
                        unsaved.n_representatives(),
                        2);
        for (const Entry &e : unsaved.entries)
          journal.append(e);
      }
      unsaved.entries.clear();
      db.save("lazy2_killed.h5", &unsaved);
    }
    build_lazily("lazy2_killed.h5", second);
    {
      Hierarchy renewed, reference;
      Database::load("lazy2_killed.h5", &renewed);
      Database::load("lazy2.h5", &reference);
      std::cout << "  the second scene after a build of the first killed "
                   "before its save keeps the journaled fits: "
                << same_level2_entries(renewed.entries, reference.entries)
                << ", journal removed: "
                << !std::filesystem::exists("lazy2_killed.h5.level2.journal")
                << std::endl;
    }
    // A level-1 run of a scene with new blocks adds its entries to the
    // file and keeps the file's level 2.
    {
      scene::VoxelGrid grid({{4, 4, 4}}, 0.01, 1);
      std::mt19937     generator(4);
      for (std::size_t v = 0; v < grid.n_voxels(); ++v)
        grid[v] = 1 + generator() % 2;
      Hierarchy             before, after;
      const Database        old = Database::load("lazy2.h5", &before);
      std::ostringstream    log;
      const DatabaseBuilder b = builder("lazy2.h5", false, "scene", 1, 0, 1);
      Hierarchy             level2;
      Database              db = b.open(palette(), level2, log);
      const std::vector<scene::VoxelGrid> grids = {grid};
      b.build(palette(), db, level2, &grids, log, false);
      const Database extended = Database::load("lazy2.h5", &after);
      bool           kept     = !before.empty() && !after.empty() &&
                  after.entries.size() == before.entries.size() &&
                  after.required_blocks() == before.required_blocks();
      for (unsigned int e = 0; kept && e < after.entries.size(); ++e)
        for (unsigned int q = 0; q < 64; ++q)
          kept &= (after.entries[e].key == before.entries[e].key &&
                   after.entries[e].material.points[q].mu ==
                     before.entries[e].material.points[q].mu);
      std::cout << "  a level-1 run adds entries ("
                << (extended.entries().size() > old.entries().size())
                << ") and keeps the file's level 2: " << kept << std::endl;
    }
    // A Scope = all build of both levels on a file that lazy runs made
    // renews the tables to require no block (they kept the lazy runs'
    // blocks): they then represent every block, and a new scene's lazy run
    // fits nothing. (The build kept the 4 blocks before, and the new
    // scene's renewed tables dropped 2 of the fits.)
    {
      std::filesystem::copy_file(
        "lazy2.h5",
        "lazy2_all.h5",
        std::filesystem::copy_options::overwrite_existing);
      build_levels("lazy2_all.h5", "all", nullptr);
      Hierarchy      complete, after;
      const Database built = Database::load("lazy2_all.h5", &complete);
      const std::vector<scene::VoxelGrid> third = {random_grid(3)};
      std::string                         distinct;
      build_levels("lazy2_all.h5", "scene", &third, nullptr, &distinct);
      const Database reread = Database::load("lazy2_all.h5", &after);
      std::cout << "  a Scope = all build over lazy tables: blocks required "
                << complete.required_blocks().size()
                << "; a new scene's lazy run then fits "
                << static_cast<long>(reread.entries().size()) -
                     static_cast<long>(built.entries().size())
                << " level-1 and "
                << static_cast<long>(after.entries.size()) -
                     static_cast<long>(complete.entries.size())
                << " level-2 entries, and says why:" << distinct << std::endl;
    }
    // A scene with more distinct parts than the budgets allow: the build
    // says how many blocks share another composition's fit.
    {
      scene::VoxelGrid grid({{8, 8, 4}}, 0.01, 1);
      std::mt19937     generator(3);
      for (std::size_t v = 0; v < grid.n_voxels(); ++v)
        grid[v] = 1 + generator() % 2;
      std::filesystem::remove("lazy2_over.h5");
      const std::vector<scene::VoxelGrid> grids = {grid};
      std::string                         distinct;
      build_levels("lazy2_over.h5", "scene", &grids, nullptr, &distinct);
      std::cout << "  over the budgets:" << distinct << std::endl;
    }
    // Level 2 with void: a 4x4x4 block whose upper 2x2x2 sub-blocks are
    // void, and one with a void sub-block at a corner and a void voxel in
    // another. Each is its own representative (a void sub-block is the
    // tables' void class), its 64 points are physical, and a reload looks
    // up the same fits.
    {
      scene::VoxelGrid grid({{8, 4, 4}}, 0.01, 1);
      for (unsigned int k = 0; k < 4; ++k)
        for (unsigned int j = 0; j < 4; ++j)
          for (unsigned int i = 0; i < 8; ++i)
            grid(i, j, k) =
              i < 4 ? (k < 2 ? 1 : 0) : (i >= 6 && j >= 2 && k >= 2 ? 0 : 2);
      grid(4, 0, 0) = 0;
      testing::remove_database("lazy2_void.h5");
      const auto fitted   = build_lazily("lazy2_void.h5", {grid}, true);
      bool       physical = true;
      for (const Metamaterial &m : fitted)
        for (const auto &p : m.points)
          physical &= (std::isfinite(p.mu) && std::isfinite(p.lambda) &&
                       std::isfinite(p.anisotropy) && p.mu > 0 &&
                       p.lambda >= 0 && p.anisotropy >= 0);
      Hierarchy      reread;
      const Database loaded = Database::load("lazy2_void.h5", &reread);
      std::vector<Metamaterial> looked_up;
      for (const auto &block : DatabaseBuilder::scene_blocks(grid))
        looked_up.push_back(reread.lookup(loaded, block));
      std::cout << "  with void: physical points: " << physical
                << ", the same after a reload: " << same(fitted, looked_up)
                << std::endl;
    }
    std::cout << "  the first scene's fits survive the second scene: "
              << same(first_alone, first_again)
              << "\n  and equal those of one build for both scenes: "
              << same(first_alone,
                      std::vector<Metamaterial>(together.begin(),
                                                together.begin() +
                                                  first_alone.size()))
              << std::endl;
  }

  {
    // One material: every block is homogeneous. Under uniaxial stress
    // (lateral faces free) and simple shear, the level-2 metamaterial of a
    // homogeneously deformed block has the fine energy; so does the level-1
    // child fit it samples. Uniaxial strain (lateral faces held) probes the
    // constrained modulus lambda + 2 mu, which the child fits lower to undo
    // the trilinear element's volumetric locking in bending: there the child
    // is softer than the coarse (paper-weight) fit.
    std::cout << "Second level, one material" << std::endl;
    std::filesystem::remove("one.h5");
    std::ostringstream    log;
    const scene::Palette  one = palette("E=1e5 nu=0.45");
    const DatabaseBuilder b   = builder("one.h5", false, "all", 2, 0, 2, 100);
    Hierarchy             built;
    Database              db = b.open(one, built, log);
    b.build(one, db, built, nullptr, log, false);
    Hierarchy                  level2;
    const Database             loaded = Database::load("one.h5", &level2);
    std::array<Combination, 8> block;
    for (auto &sub_block : block)
      sub_block.fill(1);
    const auto energy_of = [](const CoarseElement &element,
                              const Metamaterial  &m) {
      return [&element, m](const Tensor<2, 3> &F) {
        CornerDisplacements u;
        for (unsigned int v = 0; v < 8; ++v)
          {
            Tensor<1, 3> x;
            for (unsigned int d = 0; d < 3; ++d)
              x[d] = (v >> d) & 1;
            u[v] = (F - unit_symmetric_tensor<3>()) * x;
          }
        double energy;
        element.energy(u, m, energy);
        return energy;
      };
    };
    const auto fine = [&one](const Tensor<2, 3> &F) {
      material::KernelResult result;
      material::evaluate(F,
                         one[1].material_point(),
                         material::KernelOutput::energy,
                         result);
      return result.energy;
    };
    // Uniaxial stress: the lateral stretch minimizes the energy (golden
    // section search).
    const auto uniaxial_stress = [](const auto &energy, const double stretch) {
      const auto at = [&](const double lateral) {
        Tensor<2, 3> F;
        F[0][0] = stretch;
        F[1][1] = F[2][2] = lateral;
        return energy(F);
      };
      double a = 0.8, b = 1.2;
      for (unsigned int i = 0; i < 100; ++i)
        {
          const double c = b - 0.618034 * (b - a), d = a + 0.618034 * (b - a);
          if (at(c) < at(d))
            b = d;
          else
            a = c;
        }
      return at((a + b) / 2);
    };
    Tensor<2, 3> strain = unit_symmetric_tensor<3>(), shear = strain;
    strain[0][0] = 1.05;
    shear[0][1]  = 0.05;
    const CoarseElement element1(1, loaded.point_offset()),
      element2(2, level2.settings.point_offset);
    const Combination c = block[0];
    const auto        level2_energy =
      energy_of(element2, level2.lookup(loaded, block));
    const auto child_energy = energy_of(element1, loaded.lookup(c, Fit::child));
    const auto coarse_energy = energy_of(element1, loaded.lookup(c));
    for (const double stretch : {1.05, 0.95})
      for (const auto &[name, energy] :
           {std::make_pair("level 2", level2_energy),
            std::make_pair("level-1 child", child_energy)})
        testing::check_below(std::string(name) + ", uniaxial stress " +
                               std::to_string(stretch).substr(0, 4) +
                               ", relative energy difference to the fine "
                               "material",
                             std::abs(uniaxial_stress(energy, stretch) /
                                        uniaxial_stress(fine, stretch) -
                                      1),
                             0.03,
                             2);
    testing::check_below("level 2, simple shear 0.05, relative energy "
                         "difference to the fine material",
                         std::abs(level2_energy(shear) / fine(shear) - 1),
                         0.03,
                         2);
    testing::check_below("level-1 coarse fit, uniaxial strain 1.05, relative "
                         "energy difference to the fine material",
                         std::abs(coarse_energy(strain) / fine(strain) - 1),
                         0.03,
                         2);
    std::cout << "uniaxial strain 1.05: the level-1 child is softer than the "
                 "coarse fit: "
              << (child_energy(strain) < 0.95 * coarse_energy(strain))
              << std::endl;
  }

  {
    std::cout << "Bad files" << std::endl;
    std::ostringstream log;
    expect_error("missing", [] { Database::load("no_such.h5"); });
    std::ofstream("garbage.h5") << "not a database";
    expect_error("garbage", [] { Database::load("garbage.h5"); });
    {
      std::filesystem::copy_file(
        "small.h5",
        "truncated.h5",
        std::filesystem::copy_options::overwrite_existing);
      std::filesystem::resize_file("truncated.h5",
                                   std::filesystem::file_size("small.h5") / 2);
    }
    expect_error("truncated", [] { Database::load("truncated.h5"); });
    std::filesystem::create_directories("a_directory.h5");
    expect_error("a directory", [] { Database::load("a_directory.h5"); });
    // An HDF5 file of another program.
    H5Fclose(
      H5Fcreate("other_hdf5.h5", H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
    expect_error("HDF5 file of another program",
                 [] { Database::load("other_hdf5.h5"); });
    edited_copy("small.h5", "bad_attribute.h5", {{"representatives", "many"}});
    expect_error("damaged attribute",
                 [] { Database::load("bad_attribute.h5"); });
    edited_copy("small.h5", "binary_attribute.h5", {{"settings", "a\x01b"}});
    expect_error("attribute with a control character",
                 [] { Database::load("binary_attribute.h5"); });
    {
      // An attribute of two strings: read into one string's buffer, HDF5
      // wrote past it.
      edited_copy("small.h5", "array_attribute.h5", {});
      const std::string value = "ddfem metamaterial database";
      const hid_t       file =
        H5Fopen("array_attribute.h5", H5F_ACC_RDWR, H5P_DEFAULT);
      H5Adelete(file, "format");
      const hid_t   type = H5Tcopy(H5T_C_S1);
      const hsize_t two  = 2;
      H5Tset_size(type, value.size());
      const hid_t space = H5Screate_simple(1, &two, nullptr);
      const hid_t attribute =
        H5Acreate2(file, "format", type, space, H5P_DEFAULT, H5P_DEFAULT);
      H5Awrite(attribute, type, (value + value).c_str());
      H5Aclose(attribute);
      H5Sclose(space);
      H5Tclose(type);
      H5Fclose(file);
    }
    expect_error("attribute of two strings",
                 [] { Database::load("array_attribute.h5"); });
    {
      // A chunk larger than its dataset (a damaged byte in the dataset's
      // header) made HDF5 copy past its buffer. The header stores the
      // chunk's extents as 4-byte numbers followed by the element size.
      const std::string name = "entries/parameters";
      const hid_t       file = H5Fopen("small.h5", H5F_ACC_RDONLY, H5P_DEFAULT);
      const hid_t       set  = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
      const hid_t       creation = H5Dget_create_plist(set);
      std::vector<hsize_t> chunk(3);
      H5Pget_chunk(creation, 3, chunk.data());
      H5Pclose(creation);
      H5Dclose(set);
      H5Fclose(file);
      std::string pattern;
      for (const hsize_t extent : {chunk[0], chunk[1], chunk[2], hsize_t(8)})
        for (unsigned int byte = 0; byte < 4; ++byte)
          pattern += static_cast<char>((extent >> (8 * byte)) & 0xFF);
      std::string       bytes = file_bytes("small.h5");
      const std::size_t at    = bytes.find(pattern);
      // (The first such header may be another dataset's of the same
      // shape: the message names the one damaged.)
      std::cout << "chunk extents of '" << name
                << "' found in the file: " << (at != std::string::npos)
                << std::endl;
      if (at != std::string::npos)
        bytes[at + 8] = static_cast<char>(249);
      std::ofstream("bad_chunk.h5", std::ios::binary) << bytes;
    }
    expect_error("chunk larger than its dataset",
                 [] { Database::load("bad_chunk.h5"); });
    {
      // A damaged offset in a chunk index (a B-tree node of chunks, type 1:
      // "TREE", type, level, 2 bytes of entries and two 8-byte sibling
      // addresses, then per chunk its size, filter mask and 8-byte
      // offsets) moves the chunk where no read looks: HDF5 read the
      // missing chunk as zeros, without a checksum to fail, and the fit
      // statistics passed their checks so. Every index damaged in turn.
      const std::string bytes   = file_bytes("small.h5");
      unsigned int      indexes = 0, loaded = 0;
      std::size_t       at = 0;
      while ((at = bytes.find("TREE", at + 1)) != std::string::npos)
        {
          if (at + 0x27 >= bytes.size() || bytes[at + 4] != 1)
            continue;
          std::string damaged = bytes;
          damaged[at + 0x26] ^= 0x01; // the first offset's 7th byte
          std::ofstream("bad_index.h5", std::ios::binary) << damaged;
          ++indexes;
          try
            {
              Database::load("bad_index.h5");
              ++loaded;
            }
          catch (ExceptionBase &e)
            {
              const std::string message = message_of(e);
              if (message.find("without its chunk at (0") == std::string::npos)
                std::cout << "damaged chunk index: " << message << std::endl;
            }
        }
      std::cout << "chunk indexes damaged one at a time: " << (indexes > 5)
                << ", loaded without an error: " << loaded << std::endl;
    }
    expect_error("damaged chunk index of the last dataset",
                 [] { Database::load("bad_index.h5"); });
    {
      // HDF5 locks a file it opens, so one that another program writes
      // cannot be opened; that is no corruption.
      edited_copy("small.h5", "locked.h5", {});
      const int fd = open("locked.h5", O_RDWR);
      flock(fd, LOCK_EX);
      expect_error("file that another program has open for writing",
                   [] { Database::load("locked.h5"); });
      close(fd);
    }
    {
      // The void flag is stored twice, as an attribute and in the settings.
      std::string       settings = Database::load("small.h5").fingerprint();
      const std::string no_void  = " | void: 0 | ";
      settings.replace(settings.find(no_void), no_void.size(), " | void: 1 | ");
      edited_copy("small.h5", "void_disagrees.h5", {{"settings", settings}});
      expect_error("settings naming void where the attribute does not",
                   [] { Database::load("void_disagrees.h5"); });
    }
    // A palette beyond the tables' limit is named before any table is
    // allocated for it (20 materials would ask for 21^8 entries).
    std::string twenty = "E=1e5 nu=0.45";
    for (unsigned int m = 1; m < 20; ++m)
      twenty += "; E=1e5 nu=0.45";
    edited_copy("small.h5",
                "large_palette.h5",
                {{"palette", twenty}, {"palette hash", palette_hash(twenty)}});
    expect_error("20 materials", [] { Database::load("large_palette.h5"); });
    edited_copy("small.h5", "future_version.h5", {{"format version", "999"}});
    expect_error("other format version",
                 [] { Database::load("future_version.h5"); });
    edit_dataset<std::uint8_t>("small.h5",
                               "short_table.h5",
                               "lookup/symmetry",
                               [](std::vector<std::uint8_t> &values,
                                  std::vector<hsize_t>      &dims) {
                                 values.resize(5);
                                 dims = {5};
                               });
    expect_error("table of another shape",
                 [] { Database::load("short_table.h5"); });
    edit_dataset<std::int32_t>("small.h5",
                               "bad_table.h5",
                               "lookup/entry",
                               [](std::vector<std::int32_t> &values,
                                  std::vector<hsize_t> &) {
                                 values[3] = 1000;
                               });
    expect_error("table naming no entry",
                 [] { Database::load("bad_table.h5"); });
    // Lookups search the entries by key, so they must stay sorted.
    edit_dataset<std::int64_t>("small.h5",
                               "unsorted_entries.h5",
                               "entries/key",
                               [](std::vector<std::int64_t> &values,
                                  std::vector<hsize_t> &) {
                                 std::swap(values[0], values[1]);
                               });
    expect_error("entries out of order",
                 [] { Database::load("unsorted_entries.h5"); });
    {
      // A symmetry that stays in range but maps the block's entry onto
      // another combination.
      const Database    small          = Database::load("small.h5");
      const Combination c              = {{1, 2, 1, 1, 1, 1, 1, 1}};
      const Combination representative = small.symmetries().canonical(c).first;
      unsigned int      wrong          = 0;
      while (small.symmetries().apply(wrong, representative) == c)
        ++wrong;
      edit_dataset<std::uint8_t>("small.h5",
                                 "wrong_symmetry.h5",
                                 "lookup/symmetry",
                                 [&](std::vector<std::uint8_t> &values,
                                     std::vector<hsize_t> &) {
                                   values[small.combinations().key(c)] = wrong;
                                 });
      expect_error("table with a wrong symmetry",
                   [] { Database::load("wrong_symmetry.h5"); });
      // A member of a fitted orbit marked as not fitted: a lazy build would
      // fit the orbit again, as a second entry of the same key.
      edit_dataset<std::int32_t>("small.h5",
                                 "orbit_member_left_out.h5",
                                 "lookup/entry",
                                 [&](std::vector<std::int32_t> &values,
                                     std::vector<hsize_t> &) {
                                   values[small.combinations().key(c)] = -1;
                                 });
      expect_error("table that leaves out a member of a fitted orbit",
                   [] { Database::load("orbit_member_left_out.h5"); });
    }
    {
      // An entry stored under a member of its orbit other than the
      // representative it was fitted for: the first entry with such a
      // member between its neighbours' keys, so that the keys still
      // increase.
      const Database small   = Database::load("small.h5");
      const auto    &entries = small.entries();
      std::size_t    moved = entries.size(), member = 0;
      for (std::size_t e = 0; e < entries.size() && moved == entries.size();
           ++e)
        for (unsigned int g = 0; g < CubeSymmetries::size; ++g)
          {
            const std::size_t k =
              small.combinations().key(small.symmetries().apply(
                g, small.combinations().combination(entries[e].key)));
            if (k > entries[e].key &&
                (e + 1 == entries.size() || k < entries[e + 1].key))
              {
                moved  = e;
                member = k;
                break;
              }
          }
      edit_dataset<std::int64_t>("small.h5",
                                 "entry_off_representative.h5",
                                 "entries/key",
                                 [&](std::vector<std::int64_t> &values,
                                     std::vector<hsize_t> &) {
                                   values[moved] = member;
                                 });
      expect_error("entry " + std::to_string(moved) +
                     " stored under another member of its orbit",
                   [] { Database::load("entry_off_representative.h5"); });
    }
    {
      // An entry for the all-void block, which has none: the first entry's
      // key set to it (the smallest key, so the keys still increase).
      const std::size_t all_void_key =
        Database::load("full.h5").combinations().key(Combination{});
      edit_dataset<std::int64_t>("full.h5",
                                 "entry_all_void.h5",
                                 "entries/key",
                                 [&](std::vector<std::int64_t> &values,
                                     std::vector<hsize_t> &) {
                                   AssertThrow(std::int64_t(all_void_key) <
                                                 values[1],
                                               ExcInternalError());
                                   values[0] = all_void_key;
                                 });
      expect_error("an entry for the all-void block",
                   [] { Database::load("entry_all_void.h5"); });
    }
    edit_dataset<double>("small.h5",
                         "negative_mu.h5",
                         "entries/parameters",
                         [](std::vector<double> &values,
                            std::vector<hsize_t> &) {
                           values[6 * 2] =
                             -values[6 * 2]; // entry 0, point 2, mu
                         });
    expect_error("negative mu", [] { Database::load("negative_mu.h5"); });
    edit_dataset<double>("small.h5",
                         "child_direction.h5",
                         "entries/child parameters",
                         [](std::vector<double> &values,
                            std::vector<hsize_t> &) {
                           values[6 * 8 + 6 * 5 + 3] =
                             2; // entry 1, point 5, v_x: |v| >= 2
                         });
    expect_error("child direction not of unit length",
                 [] { Database::load("child_direction.h5"); });
    {
      // A flipped bit in a stored shear modulus: still a valid, physical
      // number (it changes by a few 1e-14 of itself), caught by the checksum
      // of the dataset's chunk.
      std::filesystem::copy_file(
        "small.h5",
        "flipped_bit.h5",
        std::filesystem::copy_options::overwrite_existing);
      haddr_t     address = HADDR_UNDEF;
      const hid_t file = H5Fopen("flipped_bit.h5", H5F_ACC_RDONLY, H5P_DEFAULT);
      const hid_t set  = H5Dopen2(file, "entries/parameters", H5P_DEFAULT);
      const hsize_t origin[3] = {0, 0, 0};
      unsigned int  mask      = 0;
      hsize_t       size      = 0;
      const herr_t  found =
        H5Dget_chunk_info_by_coord(set, origin, &mask, &address, &size);
      H5Dclose(set);
      H5Fclose(file);
      AssertThrow(found >= 0 && address != HADDR_UNDEF && size > 0 && mask == 0,
                  ExcMessage("entries/parameters is not stored in chunks"));
      std::fstream data("flipped_bit.h5",
                        std::ios::in | std::ios::out | std::ios::binary);
      data.seekg(address + 1); // entry 0, point 0, mu: its second lowest byte
      const char byte = data.get() ^ 0x01;
      data.seekp(address + 1);
      data.put(byte);
    }
    expect_error("a flipped bit in the parameters",
                 [] { Database::load("flipped_bit.h5"); });
    {
      // The same bit flipped in a chunk stored without its checksum and
      // with a filter mask that tells HDF5 to skip the checksum filter (a
      // damaged mask in the chunk index): HDF5 reads it unchecked.
      std::filesystem::copy_file(
        "small.h5",
        "skipped_checksum.h5",
        std::filesystem::copy_options::overwrite_existing);
      const hid_t file =
        H5Fopen("skipped_checksum.h5", H5F_ACC_RDWR, H5P_DEFAULT);
      const hid_t   set = H5Dopen2(file, "entries/parameters", H5P_DEFAULT);
      const hsize_t origin[3] = {0, 0, 0};
      hsize_t       size      = 0;
      std::uint32_t filters   = 0;
      H5Dget_chunk_storage_size(set, origin, &size);
      std::vector<char> chunk(size);
      H5Dread_chunk(set, H5P_DEFAULT, origin, &filters, chunk.data());
      chunk[1] ^= 0x01;
      const herr_t written = H5Dwrite_chunk(
        set, H5P_DEFAULT, 1, origin, size - 4, chunk.data()); // no checksum
      H5Dclose(set);
      H5Fclose(file);
      AssertThrow(written >= 0 && filters == 0,
                  ExcMessage("the chunk could not be written back"));
    }
    expect_error("a flipped bit in a chunk whose checksum is skipped",
                 [] { Database::load("skipped_checksum.h5"); });
    // HDF5 converts a stored type to the one read: keys stored as floats
    // would be truncated to integers, and a damaged type scales values.
    edit_dataset<double>("small.h5",
                         "float_keys.h5",
                         "entries/key",
                         [](std::vector<double> &, std::vector<hsize_t> &) {});
    expect_error("keys stored as floats",
                 [] { Database::load("float_keys.h5"); });
    // A median fit error above the entry's largest.
    edit_dataset<double>("small.h5",
                         "reversed_errors.h5",
                         "entries/fit error",
                         [](std::vector<double> &values,
                            std::vector<hsize_t> &) {
                           values[0] = 2 * values[1] + 1;
                         });
    expect_error("median fit error above the largest",
                 [] { Database::load("reversed_errors.h5"); });
    {
      // The chunks of a dataset share its rows evenly: five materials give
      // lookup tables of 5^8 = 390625 combinations, whose entries (1.5 MiB)
      // in a chunk of 1 MiB and a second one half full took 2 MiB, since
      // HDF5 stores a chunk whole. The symmetries (381 KiB) fit in one.
      const scene::Palette five =
        palette("E=1e5 nu=0.45; E=2e5 nu=0.45; E=4e5 nu=0.45; "
                "E=8e5 nu=0.45; E=1e6 nu=0.45");
      std::filesystem::remove("five.h5");
      const DatabaseBuilder b = builder("five.h5", false, "scene");
      Hierarchy             level2;
      Database              db                  = b.open(five, level2, log);
      const std::vector<scene::VoxelGrid> grids = {
        scene::VoxelGrid({{2, 2, 2}}, 0.01, 5)};
      b.build(five, db, level2, &grids, log, false);
      const hid_t file = H5Fopen("five.h5", H5F_ACC_RDONLY, H5P_DEFAULT);
      for (const std::string name : {"lookup/entry", "lookup/symmetry"})
        {
          const hid_t    set        = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
          const hid_t    space      = H5Dget_space(set);
          const hid_t    type       = H5Dget_type(set);
          const hssize_t n_elements = H5Sget_simple_extent_npoints(space);
          const hsize_t  bytes      = n_elements * H5Tget_size(type);
          std::cout << name << ": " << n_elements
                    << " elements, stored in at most 1 % more than their "
                       "bytes: "
                    << (H5Dget_storage_size(set) <= 1.01 * bytes) << std::endl;
          H5Tclose(type);
          H5Sclose(space);
          H5Dclose(set);
        }
      H5Fclose(file);
    }
    {
      // A dataset whose header claims far more elements than it stores.
      std::filesystem::copy_file(
        "small.h5",
        "huge_shape.h5",
        std::filesystem::copy_options::overwrite_existing);
      const hid_t file = H5Fopen("huge_shape.h5", H5F_ACC_RDWR, H5P_DEFAULT);
      H5Ldelete(file, "entries/key", H5P_DEFAULT);
      const hsize_t huge  = hsize_t(1) << 40;
      const hid_t   space = H5Screate_simple(1, &huge, nullptr);
      H5Dclose(H5Dcreate2(file,
                          "entries/key",
                          H5T_NATIVE_INT64,
                          space,
                          H5P_DEFAULT,
                          H5P_DEFAULT,
                          H5P_DEFAULT));
      H5Sclose(space);
      H5Fclose(file);
    }
    // A valid file compressed by h5repack (gzip): the mostly -1 lookup table
    // takes a small fraction of its elements' bytes.
    edit_dataset<std::int32_t>(
      "small.h5",
      "gzip.h5",
      "lookup/entry",
      [](std::vector<std::int32_t> &, std::vector<hsize_t> &) {},
      true);
    std::cout << "compressed lookup table loads, same entries: "
              << same_entries(Database::load("gzip.h5"),
                              Database::load("small.h5"))
              << std::endl;
    expect_error("dataset shape beyond its storage",
                 [] { Database::load("huge_shape.h5"); });
    edit_dataset<std::int64_t>("small.h5",
                               "huge_count.h5",
                               "entries/samples",
                               [](std::vector<std::int64_t> &values,
                                  std::vector<hsize_t> &) {
                                 values[0] = std::int64_t(1) << 32;
                               });
    expect_error("sample count beyond the range of unsigned int",
                 [] { Database::load("huge_count.h5"); });
    {
      // Level-2 tables naming a level-1 combination that has no entry: as
      // the only required block (so that the blocks stay sorted), as a
      // class key, or with a class of its own.
      const Database lazy2   = Database::load("lazy2.h5");
      std::int64_t   missing = 0;
      while (lazy2.contains(lazy2.combinations().combination(missing)))
        ++missing;
      using Edit = std::function<void(std::vector<std::int64_t> &,
                                      std::vector<hsize_t> &)>;
      for (const auto &[name, edit] : std::vector<std::pair<std::string, Edit>>{
             {"required",
              [&](std::vector<std::int64_t> &values,
                  std::vector<hsize_t>      &dims) {
                values.assign(8, -1);
                values[0] = missing;
                dims      = {1, 8};
              }},
             {"class key",
              [&](std::vector<std::int64_t> &values, std::vector<hsize_t> &) {
                values[0] = missing;
              }}})
        {
          edit_dataset<std::int64_t>("lazy2.h5",
                                     "bad_level2.h5",
                                     "level2/" + name,
                                     edit);
          expect_error("level-2 " + name + " without a level-1 entry", [] {
            Hierarchy level2;
            Database::load("bad_level2.h5", &level2);
          });
        }
      // A stage table that sends the all-void pair (the last one) to a
      // solid representative, a representative of the first stage that is
      // not in its own class, and a class for the combination without a
      // level-1 entry: each would let a lookup give a block another
      // block's fit.
      using Edit32 = std::function<void(std::vector<std::int32_t> &,
                                        std::vector<hsize_t> &)>;
      for (const auto &[name, dataset, edit] :
           std::vector<std::tuple<std::string, std::string, Edit32>>{
             {"level-2 stage table with a class for the void pair",
              "stage 1/table",
              [](std::vector<std::int32_t> &values, std::vector<hsize_t> &) {
                values.back() = 0;
              }},
             {"level-2 stage pairs with swapped representatives",
              "stage 1/pairs",
              [](std::vector<std::int32_t> &values, std::vector<hsize_t> &) {
                AssertThrow(values.size() >= 4, ExcInternalError());
                std::swap(values[0], values[2]);
                std::swap(values[1], values[3]);
              }},
             {"level-2 class of a combination without a level-1 entry",
              "class of",
              [&](std::vector<std::int32_t> &values, std::vector<hsize_t> &) {
                values[missing] = 0;
              }}})
        {
          edit_dataset<std::int32_t>("lazy2.h5",
                                     "bad_level2.h5",
                                     "level2/" + dataset,
                                     edit);
          expect_error(name, [] {
            Hierarchy level2;
            Database::load("bad_level2.h5", &level2);
          });
        }
      // A level-1 build keeps the file's level 2: opening the file checks
      // it, so the build stops before any fit (it would fit every
      // combination the lazy file lacks).
      expect_error("level-1 build of a file with a damaged level 2", [] {
        std::ostringstream    log;
        const DatabaseBuilder b = builder("bad_level2.h5", false);
        Hierarchy             level2;
        Database              db = b.open(palette(), level2, log);
        b.build(palette(), db, level2, nullptr, log, false);
      });
      std::cout << "  fits journaled: "
                << std::filesystem::exists("bad_level2.h5.journal")
                << std::endl;
    }
    expect_error("other palette", [&log] {
      open(builder("small.h5", false),
           palette("E=1e5 nu=0.45; E=2e6 nu=0.45"),
           log);
    });
    expect_error("other settings",
                 [&log] { open(builder("small.h5", true), palette(), log); });
    // The offset attribute disagrees with the settings it was fitted with:
    // lookups would place the points at the attribute's offset, and new
    // entries would be fitted for it.
    edited_copy("small.h5",
                "other_offset.h5",
                {{"coarse point offset", "0.5"}});
    expect_error("offset attribute other than its settings'",
                 [] { Database::load("other_offset.h5"); });
    // The difference names a changed value, a flag and a setting that one
    // fingerprint leaves at its default.
    {
      DatabaseSettings stored, current;
      stored.palette                       = "E=1e5 nu=0.45";
      current                              = stored;
      current.sampling.n_directions        = stored.sampling.n_directions + 2;
      current.fitting.laminate_springs     = true;
      stored.fitting.spring_regularization = 0.;
      std::cout << "settings difference: "
                << settings_difference(stored.fingerprint(),
                                       current.fingerprint())
                << "\n  of equal settings: '"
                << settings_difference(stored.fingerprint(),
                                       stored.fingerprint())
                << "'" << std::endl;
    }
    // A setting given as -0 is the setting 0 (a stream writes it "-0"): the
    // fingerprints agree, so either build's file serves the other.
    {
      const auto level1 = [](const std::string &zero) {
        const std::string text = "subsection Database\n"
                                 "  subsection Sampling\n"
                                 "    set Embedded fraction = Z\n"
                                 "    set Traction gradient = Z\n"
                                 "  end\n"
                                 "  subsection Fitting\n"
                                 "    set Regularization = Z\n"
                                 "    set Child regularization = Z\n"
                                 "    set Point floor = Z\n"
                                 "    set Spring regularization = Z\n"
                                 "  end\n"
                                 "end\n";
        return builder("zero.h5",
                       true,
                       "all",
                       1,
                       0,
                       1,
                       30,
                       0,
                       Utilities::replace_in_string(text, "Z", zero))
          .settings(palette())
          .fingerprint();
      };
      const auto level2 = [](const std::string &zero) {
        ParameterHandler prm;
        HierarchySettings::declare_parameters(prm);
        prm.parse_input_from_string("subsection Level 2\n"
                                    "  set Regularization = " +
                                    zero + "\nend\n");
        HierarchySettings settings;
        settings.parse_parameters(prm);
        return settings.fingerprint();
      };
      std::cout << "settings given as -0 and as 0: level 1 '"
                << settings_difference(level1("-0"), level1("0"))
                << "', level 2 equal: " << (level2("-0") == level2("0"))
                << std::endl;
    }
    expect_error("missing combination", [] {
      Database::load("lazy.h5").lookup({{1, 2, 2, 1, 2, 1, 1, 2}});
    });
  }
}
