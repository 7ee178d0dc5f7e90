#include <deal.II/base/exceptions.h>

#include <ddfem/base/exceptions.h>
#include <ddfem/base/files.h>
#include <ddfem/base/parsing.h>
#include <ddfem/coarsening/block_sampler.h>
#include <ddfem/coarsening/database.h>
#include <ddfem/coarsening/hierarchy.h>
#include <ddfem/solver/discretization.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <locale>
#include <optional>
#include <random>
#include <sstream>

#include "hdf5_io.h"

namespace ddfem::coarsening
{
  using namespace hdf5;

  std::string
  DatabaseSettings::describe(const scene::Palette &palette)
  {
    std::ostringstream s;
    s << std::setprecision(17);
    for (unsigned int m = 1; m <= palette.size(); ++m)
      s << (m > 1 ? "; " : "") << "mu=" << palette[m].mu
        << " lambda=" << palette[m].lambda;
    return s.str();
  }



  namespace
  {
    /// The 64-bit FNV-1a hash of @p n bytes at @p data.
    std::uint64_t
    fnv1a(const void *data, const std::size_t n)
    {
      std::uint64_t h     = 1469598103934665603ULL;
      const auto   *bytes = static_cast<const unsigned char *>(data);
      for (std::size_t i = 0; i < n; ++i)
        h = (h ^ bytes[i]) * 1099511628211ULL;
      return h;
    }
  } // namespace



  std::string
  palette_hash(const std::string &palette)
  {
    const std::uint64_t h = fnv1a(palette.data(), palette.size());
    std::ostringstream  s;
    s << std::hex << std::setw(16) << std::setfill('0') << h;
    return s.str();
  }



  std::string
  DatabaseSettings::fingerprint() const
  {
    std::ostringstream s;
    s << std::setprecision(17) << "palette: " << palette
      << " | void: " << with_void << " | patterns: " << sampling.n_directions
      << ", embedded (mixed blocks): "
      << without_negative_zero(sampling.embedded)
      << ", magnitudes: " << sampling.n_magnitudes
      << ", strains: " << sampling.min_strain << "-" << sampling.max_strain
      << ", traction gradient: "
      << without_negative_zero(sampling.traction_gradient)
      << ", stretch directions: " << sampling.n_stretch_directions;
    // Named only where it is not 0: files built before the seed was a
    // setting keep their fingerprint.
    if (sampling.seed != 0)
      s << ", seed: " << sampling.seed;
    // Named only where patterns of both kinds are drawn, whose held-out
    // split changed: such files of an earlier build are rejected.
    if (sampling.embedded > 0 && sampling.embedded < 1)
      s << ", held out per kind";
    // Named only where it is not the default, likewise.
    if (sampling.geometric_spacing)
      s << ", geometric magnitudes";
    s << " | regularization: " << without_negative_zero(fitting.regularization)
      << ", child regularization: "
      << without_negative_zero(fitting.child_regularization)
      << ", stiffness floor: " << fitting.stiffness_floor
      << ", point floor: " << without_negative_zero(fitting.point_floor)
      << ", held-out every: " << fitting.held_out_every;
    // Named only where it is on, as the seed above.
    if (fitting.laminate_springs)
      s << ", laminate springs";
    // Named only where it is set, likewise.
    if (fitting.spring_regularization)
      s << ", spring regularization: "
        << without_negative_zero(*fitting.spring_regularization);
    s << " | coarse point offset: " << point_offset;
    // Named only where the child fits' offset differs from the coarse
    // element's: before, child fits had the coarse element's offset.
    if (point_offset != child_point_offset)
      s << ", child fits at the Gauss rule";
    s << " | sampler revision: " << sampler_revision;
    return s.str();
  }



  std::string
  settings_difference(const std::string &stored, const std::string &current)
  {
    // A fingerprint's items, "name: value" or a flag's name, are separated
    // by '|' and ','; the palette's materials are separated by ';'.
    const auto items = [](const std::string &fingerprint) {
      std::vector<std::pair<std::string, std::string>> result;
      for (const std::string &group :
           Utilities::split_string_list(fingerprint, '|'))
        for (const std::string &item : Utilities::split_string_list(group, ','))
          {
            const auto colon = item.find(": ");
            if (colon == std::string::npos)
              result.emplace_back(item, "on");
            else
              result.emplace_back(item.substr(0, colon),
                                  item.substr(colon + 2));
          }
      return result;
    };
    const auto in_file = items(stored), here = items(current);
    const auto find = [](const auto &list, const std::string &name) {
      const auto item =
        std::find_if(list.begin(), list.end(), [&name](const auto &i) {
          return i.first == name;
        });
      return item == list.end() ? std::optional<std::string>() : item->second;
    };
    std::vector<std::string> names;
    for (const auto &list : {in_file, here})
      for (const auto &item : list)
        if (std::find(names.begin(), names.end(), item.first) == names.end())
          names.push_back(item.first);
    std::string result;
    for (const std::string &name : names)
      {
        // A setting one fingerprint leaves out: a flag that is off, or a
        // value at its default.
        const auto a = find(in_file, name), b = find(here, name);
        const auto absent = (a ? *a : *b) == "on" ? "off" : "default";
        if (a != b)
          result += (result.empty() ? "" : "; ") + name + ": " +
                    a.value_or(absent) + " in the file / " +
                    b.value_or(absent) + " here";
      }
    return result;
  }



  namespace
  {

    unsigned int
    count_materials(const std::string &palette)
    {
      return std::count(palette.begin(), palette.end(), ';') + 1;
    }

  } // namespace



  namespace hdf5
  {
    material::MaterialPoint
    point_from(const double *values)
    {
      material::MaterialPoint p;
      p.mu         = values[0];
      p.lambda     = values[1];
      p.anisotropy = values[2];
      for (unsigned int d = 0; d < 3; ++d)
        p.direction[d] = values[3 + d];
      return p;
    }



    bool
    is_physical(const material::MaterialPoint &p)
    {
      return std::isfinite(p.mu) && p.mu > 0 && std::isfinite(p.lambda) &&
             p.lambda >= 0 && std::isfinite(p.anisotropy) &&
             p.anisotropy >= 0 && std::abs(p.direction.norm() - 1) < 1e-6;
    }



    bool
    set_statistics(const std::array<double, 6> &stored, Entry &entry)
    {
      const auto is_count = [](const double count) {
        return count >= 0 && count == std::floor(count) &&
               count <= std::numeric_limits<unsigned int>::max();
      };
      const auto [median_error,
                  max_error,
                  min_strain,
                  max_strain,
                  n_samples,
                  n_dropped] = stored;
      if (!(std::isfinite(median_error) && median_error >= 0 &&
            std::isfinite(max_error) && median_error <= max_error &&
            std::isfinite(min_strain) && std::isfinite(max_strain) &&
            min_strain <= max_strain && is_count(n_samples) &&
            is_count(n_dropped)))
        return false;
      entry.median_error = median_error;
      entry.max_error    = max_error;
      entry.min_strain   = min_strain;
      entry.max_strain   = max_strain;
      entry.n_samples    = n_samples;
      entry.n_dropped    = n_dropped;
      return true;
    }



    unsigned int
    append_points(const double      *values,
                  const unsigned int n_points,
                  Metamaterial      &m)
    {
      for (unsigned int q = 0; q < n_points; ++q)
        {
          const material::MaterialPoint p = point_from(values + q * n_values);
          if (!is_physical(p))
            return q;
          m.points.push_back(p);
        }
      return n_points;
    }



    void
    append_values(const Metamaterial &m, std::vector<double> &values)
    {
      for (const auto &p : m.points)
        values.insert(values.end(),
                      {p.mu,
                       p.lambda,
                       p.anisotropy,
                       p.direction[0],
                       p.direction[1],
                       p.direction[2]});
    }



    void
    write_entries(const hid_t               file,
                  const std::string        &group,
                  const std::vector<Entry> &entries,
                  const unsigned int        n_points,
                  const bool                with_children)
    {
      const hsize_t             n = entries.size();
      std::vector<std::int64_t> keys, counts;
      std::vector<double>       parameters, children, errors, strains;
      for (const Entry &e : entries)
        {
          // Entries of another shape would be written misaligned (a
          // damaged journal's record, say): never in Release either.
          AssertThrow(
            e.material.points.size() == n_points &&
              e.child_material.points.size() == (with_children ? n_points : 0),
            ExcMessage(
              "The entry of key " + std::to_string(e.key) + " in " + group +
              " has " + std::to_string(e.material.points.size()) +
              " points and " + std::to_string(e.child_material.points.size()) +
              " child points, not " + std::to_string(n_points) + " and " +
              std::to_string(with_children ? n_points : 0) +
              ": it cannot be saved."));
          keys.push_back(e.key);
          append_values(e.material, parameters);
          append_values(e.child_material, children);
          errors.insert(errors.end(), {e.median_error, e.max_error});
          strains.insert(strains.end(), {e.min_strain, e.max_strain});
          counts.insert(counts.end(), {e.n_samples, e.n_dropped});
        }
      write_dataset(file, group + "/key", {n}, keys);
      write_dataset(file,
                    group + "/parameters",
                    {n, n_points, n_values},
                    parameters);
      if (with_children)
        write_dataset(file,
                      group + "/child parameters",
                      {n, n_points, n_values},
                      children);
      write_dataset(file, group + "/fit error", {n, 2}, errors);
      write_dataset(file, group + "/strain range", {n, 2}, strains);
      write_dataset(file, group + "/samples", {n, 2}, counts);
    }



    hsize_t
    dataset_length(const hid_t file, const std::string &name)
    {
      check(H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0,
            "has no dataset '" + name + "'");
      const Handle set(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose);
      check(set.valid(), "cannot open the dataset '" + name + "'");
      const std::vector<hsize_t> shape = dataset_shape(set, name);
      check(!shape.empty(), "has an empty-shaped dataset '" + name + "'");
      return shape[0];
    }



    std::vector<Entry>
    read_entries(const hid_t        file,
                 const std::string &group,
                 const unsigned int n_points,
                 const bool         with_children)
    {
      const hsize_t n = dataset_length(file, group + "/key");
      const auto keys = read_dataset<std::int64_t>(file, group + "/key", {n});
      const auto parameters = read_dataset<double>(file,
                                                   group + "/parameters",
                                                   {n, n_points, n_values});
      const auto children   = with_children ?
                                read_dataset<double>(file,
                                                   group + "/child parameters",
                                                   {n, n_points, n_values}) :
                                std::vector<double>();
      const auto errors =
        read_dataset<double>(file, group + "/fit error", {n, 2});
      const auto strains =
        read_dataset<double>(file, group + "/strain range", {n, 2});
      const auto counts =
        read_dataset<std::int64_t>(file, group + "/samples", {n, 2});
      std::vector<Entry> entries;
      for (hsize_t e = 0; e < n; ++e)
        {
          Entry entry;
          check(keys[e] >= 0 && (e == 0 || keys[e] > keys[e - 1]),
                "has an invalid key at " + group + " " + std::to_string(e));
          entry.key = keys[e];
          // Entry e's points in @p values, checked to be physical.
          const auto read_points = [&](const std::vector<double> &values,
                                       const std::string         &name,
                                       Metamaterial              &m) {
            const unsigned int q =
              append_points(&values[e * n_points * n_values], n_points, m);
            check(q == n_points,
                  "has non-physical " + name + " at " + group + " " +
                    std::to_string(e) + ", point " + std::to_string(q));
          };
          read_points(parameters, "parameters", entry.material);
          if (with_children)
            read_points(children, "child parameters", entry.child_material);
          check(set_statistics({{errors[2 * e],
                                 errors[2 * e + 1],
                                 strains[2 * e],
                                 strains[2 * e + 1],
                                 double(counts[2 * e]),
                                 double(counts[2 * e + 1])}},
                               entry),
                "has invalid fit statistics at " + group + " " +
                  std::to_string(e));
          entries.push_back(entry);
        }
      return entries;
    }
  } // namespace hdf5



  Database::Database(const DatabaseSettings &settings,
                     const unsigned int      n_materials)
    : palette_description(settings.palette)
    , settings_fingerprint(settings.fingerprint())
    , coarse_point_offset(settings.point_offset)
    , index(n_materials, settings.with_void)
    , entry_key_of(index.size(), -1)
    , symmetry_of(index.size(), 0)
  {
    // The tables index keys with 32-bit integers. The palettes and files
    // ddfem reads have at most 9 ids (9^8 keys), which the checks of the
    // scene and of Database::load ensure.
    AssertThrow(index.size() <=
                  std::size_t(std::numeric_limits<std::int32_t>::max()),
                ExcMessage("A database of " + std::to_string(n_materials) +
                           " materials" +
                           (settings.with_void ? " and void" : "") +
                           " has more combinations than its 32-bit tables "
                           "index."));
  }



  const Entry &
  Database::entry(const std::int32_t entry_key) const
  {
    const auto position = find_key(fitted, entry_key);
    Assert(entry_key >= 0 && position != fitted.end() &&
             position->key == std::size_t(entry_key),
           ExcInternalError());
    return *position;
  }



  bool
  Database::contains(const Combination &c) const
  {
    return index.contains(c) && entry_key_of[index.key(c)] >= 0;
  }



  Metamaterial
  Database::lookup(const Combination &c, const Fit fit) const
  {
    AssertThrow(contains(c),
                ExcMessage("The metamaterial database has no entry for the "
                           "block with material ids " +
                           [&c]() {
                             std::string s;
                             for (const auto id : c)
                               s += std::to_string(id) + " ";
                             return s;
                           }() +
                           "(child 0 first)."));
    const std::size_t key   = index.key(c);
    const Entry      &entry = this->entry(entry_key_of[key]);
    return transform(fit == Fit::coarse ? entry.material : entry.child_material,
                     group,
                     symmetry_of[key]);
  }



  std::vector<Combination>
  Database::missing(const std::vector<Combination> &combinations) const
  {
    std::vector<Combination> result;
    for (const Combination &c : combinations)
      {
        index.check_covered(c);
        if (!all_void(c) && !contains(c))
          result.push_back(group.canonical(c).first);
      }
    std::sort(result.begin(), result.end());
    result.erase(std::unique(result.begin(), result.end()), result.end());
    return result;
  }



  void
  Database::add(const Entry &entry)
  {
    AssertThrow(representatives == 0,
                ExcMessage("A compressed database cannot take new entries."));
    const Combination representative = index.combination(entry.key);
    Assert(group.canonical(representative).first == representative,
           ExcInternalError());
    if (entry_key_of[entry.key] >= 0)
      return;
    // Keep the entries sorted by key: the file does not depend on the
    // order in which threads finish.
    fitted.insert(find_key(fitted, entry.key), entry);
    for (unsigned int g = 0; g < CubeSymmetries::size; ++g)
      {
        const std::size_t key = index.key(group.apply(g, representative));
        if (entry_key_of[key] < 0)
          {
            entry_key_of[key] = entry.key;
            symmetry_of[key]  = g;
          }
      }
  }



  void
  Database::check_not_read_only(const std::string &file)
  {
    AssertThrow(!std::filesystem::exists(file) ||
                  access(file.c_str(), W_OK) == 0,
                ExcMessage("The metamaterial database '" + file +
                           "' (Database/File) is read-only, and this run "
                           "would add to it. Make it writable, or set "
                           "Database/File to a writable copy."));
  }



  void
  Database::save(const std::string &file, const Hierarchy *level2) const
  {
    check_not_read_only(file);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); // our messages only
    const std::string temporary = ResultFile::partial_name(file);
    // What keeps the new entries should the file stay as it is.
    const auto kept = [&file]() -> std::string {
      return Journal::exists(file) ||
                 Journal::exists(level2_journal_base(file)) ?
               " Its journal keeps the new entries." :
               "";
    };
    // The file is written under another name and replaces the old one only
    // once HDF5 has closed it without error: a full disk leaves the old
    // file and no partial one.
    Handle h5(
      H5Fcreate(temporary.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
      H5Fclose);
    AssertThrow(h5.valid(),
                ExcMessage("Cannot create the database file " + temporary +
                           " (does its directory exist and is it "
                           "writable?)."));
    std::error_code ignored;
    try
      {
        write_attribute(h5, "format", "ddfem metamaterial database");
        write_attribute(h5,
                        "format version",
                        std::to_string(database_format_version));
        write_attribute(h5, "code version", "ddfem 0.1");
        write_attribute(h5, "palette", palette_description);
        write_attribute(h5, "palette hash", palette_hash(palette_description));
        write_attribute(h5, "with void", index.with_void() ? "1" : "0");
        write_attribute(h5, "settings", settings_fingerprint);
        {
          std::ostringstream offset;
          offset << std::setprecision(17) << coarse_point_offset;
          write_attribute(h5, "coarse point offset", offset.str());
        }
        write_attribute(h5, "representatives", std::to_string(representatives));

        write_entries(h5, "entries", fitted, 8, true);
        {
          // The file refers to entries by their position.
          std::vector<std::int32_t> entry_of(entry_key_of.size(), -1);
          for (std::size_t k = 0; k < entry_of.size(); ++k)
            if (entry_key_of[k] >= 0)
              entry_of[k] = &entry(entry_key_of[k]) - fitted.data();
          write_dataset(h5, "lookup/entry", {hsize_t(index.size())}, entry_of);
        }
        write_dataset(h5,
                      "lookup/symmetry",
                      {hsize_t(index.size())},
                      symmetry_of);
        if (level2 != nullptr && !level2->empty())
          level2->save(h5);
        AssertThrow(h5.close_now(), ExcMessage("HDF5 could not close it."));
        // On the disk before it replaces the old file, and before the
        // caller removes the journal of its entries.
        AssertThrow(sync_to_disk(temporary),
                    ExcMessage("It could not be flushed to the disk."));
      }
    catch (const ExceptionBase &e)
      {
        // Closed before it is removed (HDF5 would write to it still).
        h5.close_now();
        std::filesystem::remove(temporary, ignored);
        AssertThrow(false,
                    ExcMessage("Cannot write the database file " + temporary +
                               " (is the disk full?): " + message_of(e) + " " +
                               file + " is unchanged." + kept()));
      }
    catch (...) // out of memory, say: no partial file either
      {
        h5.close_now();
        std::filesystem::remove(temporary, ignored);
        throw;
      }
    // The new file keeps the old one's group, where the user may give it
    // (a member of the group may), and its mode: a database shared by a
    // group stays the group's. Best effort: the save itself succeeded.
    if (struct stat old; ::stat(file.c_str(), &old) == 0)
      {
        // Where the user is not in the old file's group, chown refuses and
        // the new file keeps the user's group.
        [[maybe_unused]] const int status =
          ::chown(temporary.c_str(), -1, old.st_gid);
        std::filesystem::permissions(temporary,
                                     static_cast<std::filesystem::perms>(
                                       old.st_mode & 07777),
                                     ignored);
      }
    std::error_code error;
    std::filesystem::rename(temporary, file, error);
    if (error)
      std::filesystem::remove(temporary, ignored);
    AssertThrow(!error,
                ExcMessage("Cannot replace the database file " + file +
                           " (Database/File): " + error.message() + "." +
                           kept()));
    // The rename itself (best effort: not every file system syncs a
    // directory).
    sync_to_disk(std::filesystem::absolute(file).parent_path().string());
  }



  Database
  Database::load(const std::string &file, Hierarchy *level2)
  {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); // our messages only
    const std::string where = "The metamaterial database file '" + file + "' ";
    std::error_code   error;
    AssertThrow(std::filesystem::exists(file, error),
                ExcMessage(
                  where + (error ? "cannot be found: " + error.message() + "." :
                                   "does not exist.")));
    const std::string kind = non_regular_kind(file);
    AssertThrow(kind.empty(),
                ExcMessage(where + "is " + kind + ", not a regular file."));
    // A file that cannot be read (permissions, say) is not a corrupt one,
    // which a user might delete.
    std::FILE *const probe      = std::fopen(file.c_str(), "rb");
    const int        open_error = errno;
    if (probe != nullptr)
      std::fclose(probe);
    AssertThrow(probe != nullptr,
                ExcMessage(where + "cannot be read: " +
                           std::strerror(open_error) + "."));
    try
      {
        check(H5Fis_hdf5(file.c_str()) > 0,
              "is not an HDF5 file (corrupt or truncated?)");
        const Handle h5(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT),
                        H5Fclose);
        check(h5.valid(),
              lock_failed() ?
                "cannot be opened: HDF5 could not lock it. Another program "
                "may have it open for writing (an HDF5 viewer or script?), "
                "or the file system may not support locks (then set the "
                "environment variable HDF5_USE_FILE_LOCKING=FALSE)" :
                "cannot be opened (corrupt or truncated?)");
        check(H5Aexists(h5, "format") > 0 &&
                read_attribute(h5, "format") == "ddfem metamaterial database",
              "is not a ddfem metamaterial database");
        const std::string version = read_attribute(h5, "format version");
        check(version == std::to_string(database_format_version),
              "has format version " + version + ", this program reads " +
                std::to_string(database_format_version));

        DatabaseSettings settings;
        settings.palette = read_attribute(h5, "palette");
        check(read_attribute(h5, "palette hash") ==
                palette_hash(settings.palette),
              "has a palette that does not match its hash (corrupt file?)");
        const std::string with_void = read_attribute(h5, "with void");
        check(with_void == "0" || with_void == "1",
              "has an invalid 'with void' attribute '" + with_void + "'");
        settings.with_void             = with_void == "1";
        const unsigned int n_materials = count_materials(settings.palette);
        check(
          n_materials + (settings.with_void ? 1 : 0) <= 9,
          "has a palette of " + std::to_string(n_materials) +
            " materials; databases hold at most 9 material ids, void included");
        settings.point_offset =
          read_number_attribute(h5, "coarse point offset");
        const auto [low, high] = solver::point_offset_range(1);
        check(solver::valid_point_offset(settings.point_offset, 1),
              "has a coarse point offset of " +
                Utilities::to_string(settings.point_offset) +
                ", which is not in [" + format_number(low) + ", " +
                format_number(high) + ")");
        const std::string fingerprint = read_attribute(h5, "settings");
        // The settings name the void flag too (DatabaseSettings::
        // fingerprint()): the two must agree.
        check(fingerprint.find(" | void: " + with_void + " | ") !=
                std::string::npos,
              "has a 'with void' attribute " + with_void +
                " that its 'settings' attribute does not name (corrupt "
                "file?)");
        // ... and so must the offset, at which the entries were fitted: the
        // number after its name, up to the next item.
        const std::string offset       = " | coarse point offset: ";
        const std::size_t named        = fingerprint.find(offset);
        double            named_offset = 0;
        if (named != std::string::npos)
          {
            std::istringstream text(fingerprint.substr(named + offset.size()));
            text.imbue(std::locale::classic());
            text >> named_offset;
            if (!text || (text.peek() != std::char_traits<char>::eof() &&
                          text.peek() != ',' && text.peek() != ' '))
              named_offset = std::numeric_limits<double>::quiet_NaN();
          }
        check(named != std::string::npos &&
                named_offset == settings.point_offset,
              "has a 'coarse point offset' attribute " +
                Utilities::to_string(settings.point_offset) +
                " that its 'settings' attribute does not name (corrupt "
                "file?)");
        Database db(settings, n_materials);
        db.settings_fingerprint = fingerprint;
        const double representatives =
          read_number_attribute(h5, "representatives");
        check(representatives >= 0 && representatives < 1e9 &&
                representatives == std::floor(representatives),
              "has a representatives count of " +
                Utilities::to_string(representatives) +
                ", which is not a count");
        db.representatives = representatives;

        db.fitted            = read_entries(h5, "entries", 8, true);
        const hsize_t n_keys = db.index.size();
        db.entry_key_of =
          read_dataset<std::int32_t>(h5, "lookup/entry", {n_keys});
        db.symmetry_of =
          read_dataset<std::uint8_t>(h5, "lookup/symmetry", {n_keys});
        // read_entries() checked that the keys increase. An entry is fitted
        // for its orbit's representative, and the all-void block has none.
        for (const Entry &e : db.fitted)
          {
            check(e.key < n_keys, "has an entry key beyond the palette");
            const Combination c = db.index.combination(e.key);
            check(!all_void(c) && db.group.canonical(c).first == c,
                  "has an entry at key " + std::to_string(e.key) +
                    ", which is " +
                    (all_void(c) ? "the all-void block" :
                                   "not its orbit's representative"));
          }
        const std::int64_t n = db.fitted.size();
        // Positions in the file, entry keys in memory.
        std::vector<bool> used(n, false);
        for (std::size_t k = 0; k < n_keys; ++k)
          {
            std::int32_t &e = db.entry_key_of[k];
            check(e >= -1 && e < n && db.symmetry_of[k] < CubeSymmetries::size,
                  "has an invalid lookup table at combination " +
                    std::to_string(k));
            // A compressed database was complete (Database/Scope = all)
            // and takes no new entries: every block but the all-void one
            // is looked up.
            check(db.representatives == 0 || e >= 0 ||
                    all_void(db.index.combination(k)),
                  "is compressed but has no entry for combination " +
                    std::to_string(k));
            if (e >= 0)
              {
                used[e] = true;
                e       = db.fitted[e].key;
              }
          }
        check(std::find(used.begin(), used.end(), false) == used.end(),
              "has an entry that no combination looks up");
        // A combination's symmetry maps its entry's block onto the
        // combination whose entry and symmetry it took: itself,
        // uncompressed; its representative, compressed, which keeps its own
        // (Database::compress()). A flipped value that stays in range would
        // rotate another block's material into it.
        std::size_t n_representatives = 0;
        for (std::size_t k = 0; k < n_keys; ++k)
          if (const std::int32_t e = db.entry_key_of[k]; e >= 0)
            {
              const std::size_t r = db.index.key(
                db.group.apply(db.symmetry_of[k], db.index.combination(e)));
              check((r == k || db.representatives > 0) &&
                      db.entry_key_of[r] == e &&
                      db.symmetry_of[r] == db.symmetry_of[k],
                    "has a lookup table whose symmetry at combination " +
                      std::to_string(k) + " does not map its entry onto " +
                      (db.representatives > 0 ? "a representative" : "it"));
              n_representatives += (r == k);
            }
        check(n_representatives <= db.representatives ||
                db.representatives == 0,
              "has " + std::to_string(n_representatives) +
                " representatives in its lookup table, more than its count " +
                std::to_string(db.representatives));
        // ... and every member of an entry's orbit is looked up there (a
        // member left out would be fitted again, as a second entry).
        if (db.representatives == 0)
          for (const Entry &e : db.fitted)
            for (unsigned int g = 0; g < CubeSymmetries::size; ++g)
              check(db.entry_key_of[db.index.key(
                      db.group.apply(g, db.index.combination(e.key)))] ==
                      std::int32_t(e.key),
                    "has a lookup table that leaves out a combination of "
                    "the orbit of entry key " +
                      std::to_string(e.key));
        if (level2 != nullptr && !level2->load(h5, db))
          *level2 = Hierarchy();
        return db;
      }
    catch (const FileProblem &problem)
      {
        AssertThrow(false, ExcMessage(where + problem.what + "."));
      }
    return Database(DatabaseSettings(), 1);
  }



  std::vector<unsigned int>
  farthest_point_sampling(const std::vector<std::vector<double>> &points,
                          const unsigned int                      k,
                          const std::vector<unsigned int>        &first)
  {
    const auto distance = [&points](const unsigned int a,
                                    const unsigned int b) {
      double d = 0;
      for (unsigned int i = 0; i < points[a].size(); ++i)
        d += (points[a][i] - points[b][i]) * (points[a][i] - points[b][i]);
      return std::sqrt(d);
    };
    std::vector<unsigned int> picked;
    std::vector<double>       nearest(points.size(),
                                std::numeric_limits<double>::max());
    const auto                pick = [&](const unsigned int next) {
      picked.push_back(next);
      for (unsigned int p = 0; p < points.size(); ++p)
        nearest[p] = std::min(nearest[p], distance(p, next));
    };
    for (const unsigned int p : first)
      pick(p);
    // Once every point coincides with a picked one, the farthest is one
    // already picked: stop rather than pick it again.
    while (picked.size() < k)
      {
        const auto farthest = std::max_element(nearest.begin(), nearest.end());
        if (farthest == nearest.end() || !(*farthest > 0))
          break;
        pick(farthest - nearest.begin());
      }
    return picked;
  }



  std::vector<CornerDisplacements>
  feature_deformations(const unsigned int  n,
                       const double        strain,
                       const std::uint64_t seed)
  {
    // A homogeneous block (nu = 0.4) under the sampler's force patterns:
    // deformations of the kind the database was fitted to, in place of
    // arbitrary corner motions that would probe unsampled modes.
    material::MaterialPoint reference;
    reference.mu     = 1;
    reference.lambda = 4;
    std::array<std::vector<material::MaterialPoint>, 8> children;
    children.fill(std::vector<material::MaterialPoint>(8, reference));
    SamplingSettings settings;
    settings.embedded     = 0;
    settings.n_directions = n;
    settings.n_magnitudes = 1;
    settings.min_strain   = strain;
    settings.max_strain   = strain;
    unsigned int                     n_dropped;
    std::vector<CornerDisplacements> result;
    for (const Sample &s :
         BlockSampler(children).sample(settings, seed, n_dropped))
      result.push_back(s.corners);
    return result;
  }



  namespace
  {
    /// The log-energies of @p m under @p deformations (a feature vector).
    std::vector<double>
    log_energies(const CoarseElement                    &element,
                 const Metamaterial                     &m,
                 const std::vector<CornerDisplacements> &deformations)
    {
      std::vector<double> result;
      for (const auto &u : deformations)
        {
          double energy;
          AssertThrow(element.energy(u, m, energy) && energy > 0,
                      ExcInternalError());
          result.push_back(std::log(energy));
        }
      return result;
    }
  } // namespace



  std::vector<std::vector<double>>
  Database::features(const CoarseElement                    &element,
                     const std::vector<CornerDisplacements> &deformations,
                     std::vector<std::size_t>               &keys,
                     const Fit                               fit) const
  {
    std::vector<std::vector<double>> result;
    keys.clear();
    for (std::size_t key = 0; key < index.size(); ++key)
      {
        const Combination c = index.combination(key);
        if (entry_key_of[key] < 0 || all_void(c))
          continue;
        result.push_back(log_energies(element, lookup(c, fit), deformations));
        keys.push_back(key);
      }
    return result;
  }



  Clustering
  cluster(const std::vector<std::vector<double>> &features,
          const unsigned int                      k,
          const std::uint64_t                     seed,
          std::vector<unsigned int>               required)
  {
    AssertThrow(!features.empty(),
                ExcMessage("Farthest point sampling needs at least one "
                           "point: a database without entries can be "
                           "neither compressed nor clustered for level 2."));
    std::sort(required.begin(), required.end());
    required.erase(std::unique(required.begin(), required.end()),
                   required.end());
    // Sampling starts from a seeded point of the candidates: all points,
    // or the required ones if they are too many to keep.
    const bool        among_required = (required.size() > k);
    const std::size_t n_candidates =
      among_required ? required.size() : features.size();
    std::mt19937_64    generator(seed);
    const unsigned int first =
      std::uniform_int_distribution<std::size_t>(0,
                                                 n_candidates - 1)(generator);
    Clustering result;
    if (among_required)
      {
        std::vector<std::vector<double>> subset;
        for (const unsigned int p : required)
          subset.push_back(features[p]);
        for (const unsigned int i : farthest_point_sampling(subset, k, {first}))
          result.representatives.push_back(required[i]);
      }
    else
      result.representatives =
        farthest_point_sampling(features,
                                k,
                                required.empty() ?
                                  std::vector<unsigned int>{first} :
                                  required);

    result.nearest.resize(features.size());
    for (unsigned int p = 0; p < features.size(); ++p)
      {
        double best_distance = std::numeric_limits<double>::max();
        for (unsigned int r = 0; r < result.representatives.size(); ++r)
          {
            const auto &a = features[p],
                       &b = features[result.representatives[r]];
            double d      = 0;
            for (unsigned int i = 0; i < a.size() && d < best_distance; ++i)
              d += (a[i] - b[i]) * (a[i] - b[i]);
            if (d < best_distance)
              {
                best_distance     = d;
                result.nearest[p] = r;
              }
          }
      }
    // Points with equal features stay apart if both are representatives.
    for (unsigned int r = 0; r < result.representatives.size(); ++r)
      result.nearest[result.representatives[r]] = r;
    return result;
  }



  unsigned int
  Database::compress(const unsigned int                      k,
                     const CoarseElement                    &element,
                     const std::vector<CornerDisplacements> &deformations)
  {
    AssertThrow(k > 0,
                ExcMessage("Compression needs at least one "
                           "representative."));
    std::vector<std::size_t> keys;
    const Clustering         clusters =
      cluster(features(element, deformations, keys), k, 20260101);

    // Redirect every combination to its nearest representative.
    std::vector<std::int32_t> new_entry_key_of(index.size(), -1);
    std::vector<std::uint8_t> new_symmetry_of(index.size(), 0);
    for (unsigned int p = 0; p < keys.size(); ++p)
      {
        const std::size_t representative =
          keys[clusters.representatives[clusters.nearest[p]]];
        new_entry_key_of[keys[p]] = entry_key_of[representative];
        new_symmetry_of[keys[p]]  = symmetry_of[representative];
      }

    // Drop the entries nobody uses.
    std::vector<std::int32_t> used;
    for (const std::int32_t e : new_entry_key_of)
      if (e >= 0)
        used.push_back(e);
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    std::vector<Entry> kept;
    for (const Entry &e : fitted)
      if (std::binary_search(used.begin(), used.end(), std::int32_t(e.key)))
        kept.push_back(e);
    fitted          = kept;
    entry_key_of    = new_entry_key_of;
    symmetry_of     = new_symmetry_of;
    representatives = k;
    return clusters.representatives.size();
  }



  namespace
  {
    constexpr std::uint32_t record_magic = 0x4444464dU; // "DDFM"

    /// The checksum of a journal record: FNV-1a over its bytes.
    std::uint64_t
    checksum(const std::vector<double> &values)
    {
      return fnv1a(values.data(), values.size() * sizeof(double));
    }

    /// The message for a journal file that cannot be written.
    std::string
    cannot_write(const std::string &journal)
    {
      return "Cannot write the build journal " + journal +
             " (next to Database/File): is the disk full or the directory "
             "read-only?";
    }
  } // namespace



  namespace
  {
    /**
     * The points and child points of an entry of level @p level: 8 and 8
     * at level 1, 64 and none at level 2 (the lookups of a level read
     * them so).
     */
    std::pair<unsigned int, unsigned int>
    record_shape(const unsigned int level)
    {
      Assert(level == 1 || level == 2, ExcInternalError());
      return level == 1 ? std::pair(8u, 8u) : std::pair(64u, 0u);
    }



    /**
     * The complete records of the journal @p name (see Journal::read()),
     * and in @p valid_end the length of the journal up to the end of the
     * last of them.
     */
    std::vector<Entry>
    read_journal(const std::string &name,
                 const std::string &fingerprint,
                 const std::size_t  n_keys,
                 const unsigned int level,
                 std::uintmax_t    &valid_end)
    {
      std::vector<Entry> entries;
      valid_end              = 0;
      const std::string kind = non_regular_kind(name);
      AssertThrow(kind.empty(),
                  ExcMessage("The build journal " + name + " is " + kind +
                             ". Remove it or choose another Database/File."));
      std::FILE *in         = std::fopen(name.c_str(), "rb");
      const int  open_error = errno;
      // Only a missing journal holds no records: one that cannot be read
      // would be cut to nothing by the next Journal.
      AssertThrow(in != nullptr || open_error == ENOENT,
                  ExcMessage("The build journal " + name +
                             " cannot be read: " + std::strerror(open_error) +
                             ". Make it readable, or delete it (the entries "
                             "it held are fitted again)."));
      if (in == nullptr)
        return entries;
      std::uint64_t length = 0;
      std::string   stored;
      if (std::fread(&length, sizeof(length), 1, in) == 1 && length < 100000)
        {
          stored.resize(length);
          if (std::fread(stored.data(), 1, length, in) != length)
            stored.clear();
        }
      if (stored != fingerprint)
        {
          std::fclose(in);
          AssertThrow(!stored.empty(),
                      ExcMessage("The build journal " + name +
                                 " has no readable header: it is damaged or "
                                 "not a journal. Delete it (the entries it "
                                 "held are fitted again)."));
          AssertThrow(false,
                      ExcMessage("The build journal " + name +
                                 " belongs to a build with other settings (" +
                                 settings_difference(stored, fingerprint) +
                                 "). Delete it (the entries it held are then "
                                 "fitted with these settings), or restore "
                                 "those settings to resume that build."));
        }
      valid_end                    = std::ftell(in);
      const unsigned int  n_header = 9;
      std::vector<double> values(n_header);
      std::uint32_t       magic;
      std::uint64_t       sum;
      const auto [n_level_points, n_level_children] = record_shape(level);
      while (std::fread(&magic, sizeof(magic), 1, in) == 1 &&
             magic == record_magic &&
             std::fread(values.data(), sizeof(double), n_header, in) ==
               n_header &&
             values[7] == n_level_points && values[8] == n_level_children)
        {
          const unsigned int n_stored =
            (n_level_points + n_level_children) * n_values;
          values.resize(n_header + n_stored);
          if (std::fread(values.data() + n_header,
                         sizeof(double),
                         n_stored,
                         in) != n_stored ||
              std::fread(&sum, sizeof(sum), 1, in) != 1 ||
              sum != checksum(values))
            break;
          if (!(values[0] >= 0 && values[0] < n_keys &&
                values[0] == std::floor(values[0])))
            break;
          Entry e;
          e.key = values[0];
          if (!(set_statistics({{values[1],
                                 values[2],
                                 values[3],
                                 values[4],
                                 values[5],
                                 values[6]}},
                               e) &&
                append_points(values.data() + n_header,
                              n_level_points,
                              e.material) == n_level_points &&
                append_points(values.data() + n_header +
                                n_level_points * n_values,
                              n_level_children,
                              e.child_material) == n_level_children))
            break;
          entries.push_back(e);
          valid_end = std::ftell(in);
          values.resize(n_header);
        }
      std::fclose(in);
      return entries;
    }
  } // namespace



  Journal::Journal(const std::string &database_file,
                   const std::string &fingerprint,
                   const std::size_t  n_keys,
                   const unsigned int level)
    : name(file_name(database_file))
    , level(level)
  {
    // A new journal gets its header under another name first: a reader
    // (or a build killed meanwhile) never sees half a header.
    if (!std::filesystem::exists(name))
      {
        const std::string partial = ResultFile::partial_name(name);
        std::FILE        *header  = std::fopen(partial.c_str(), "wb");
        AssertThrow(header != nullptr, ExcMessage(cannot_write(partial)));
        const std::uint64_t length = fingerprint.size();
        const bool          written =
          std::fwrite(&length, sizeof(length), 1, header) == 1 &&
          std::fwrite(fingerprint.data(), 1, length, header) == length;
        const bool      closed = std::fclose(header) == 0;
        std::error_code renamed;
        if (written && closed)
          std::filesystem::rename(partial, name, renamed);
        if (!written || !closed || renamed)
          {
            std::filesystem::remove(partial);
            AssertThrow(false, ExcMessage(cannot_write(name)));
          }
      }
    else if (std::filesystem::is_regular_file(name))
      {
        // A build interrupted while appending leaves a torn record, and
        // read() stops there: cut it off, or the records appended now
        // would follow it unread.
        std::uintmax_t valid_end;
        read_journal(name, fingerprint, n_keys, level, valid_end);
        std::error_code error;
        if (std::filesystem::file_size(name, error) > valid_end && !error)
          std::filesystem::resize_file(name, valid_end, error);
        AssertThrow(!error, ExcMessage(cannot_write(name)));
      }
    file = std::fopen(name.c_str(), "ab");
    AssertThrow(file != nullptr, ExcMessage(cannot_write(name)));
    // (Not std::filesystem::file_size(), which throws for a device.)
    std::fseek(file, 0, SEEK_END);
    valid_end = std::max(std::ftell(file), 0L);
  }



  Journal::~Journal()
  {
    if (file != nullptr)
      std::fclose(file);
  }



  void
  Journal::append(const Entry &entry)
  {
    // A record of another shape would end the records read back, and the
    // next Journal would cut it and all after it: never in Release either.
    AssertThrow(std::pair(unsigned(entry.material.points.size()),
                          unsigned(entry.child_material.points.size())) ==
                  record_shape(level),
                ExcInternalError());
    std::vector<double> values = {double(entry.key),
                                  entry.median_error,
                                  entry.max_error,
                                  entry.min_strain,
                                  entry.max_strain,
                                  double(entry.n_samples),
                                  double(entry.n_dropped),
                                  double(entry.material.points.size()),
                                  double(entry.child_material.points.size())};
    append_values(entry.material, values);
    append_values(entry.child_material, values);
    const std::uint64_t sum = checksum(values);
    AssertThrow(file != nullptr,
                ExcMessage(cannot_write(name) +
                           " An earlier record could not be written, and the "
                           "journal takes no more."));
    // A record that is not written whole is cut off, and the journal takes
    // no more: records appended after a torn one would not be read. The
    // build stops here rather than fit on without saving.
    if (std::fwrite(&record_magic, sizeof(record_magic), 1, file) == 1 &&
        std::fwrite(values.data(), sizeof(double), values.size(), file) ==
          values.size() &&
        std::fwrite(&sum, sizeof(sum), 1, file) == 1 && std::fflush(file) == 0)
      valid_end +=
        sizeof(record_magic) + sizeof(double) * values.size() + sizeof(sum);
    else
      {
        std::fclose(file);
        file = nullptr;
        std::error_code error;
        std::filesystem::resize_file(name, valid_end, error);
        AssertThrow(false, ExcMessage(cannot_write(name)));
      }
  }



  std::vector<Entry>
  Journal::read(const std::string &database_file,
                const std::string &fingerprint,
                const std::size_t  n_keys,
                const unsigned int level)
  {
    std::uintmax_t valid_end;
    return read_journal(
      file_name(database_file), fingerprint, n_keys, level, valid_end);
  }



  void
  Journal::remove(const std::string &database_file)
  {
    std::filesystem::remove(file_name(database_file));
  }



  bool
  Journal::exists(const std::string &database_file)
  {
    return std::filesystem::exists(file_name(database_file));
  }



  std::string
  Journal::file_name(const std::string &database_file)
  {
    return database_file + ".journal";
  }



  std::string
  level2_journal_base(const std::string &database_file)
  {
    return database_file + ".level2";
  }



  std::vector<std::string>
  database_files(const std::string &database_file)
  {
    const std::string level1 = Journal::file_name(database_file);
    const std::string level2 =
      Journal::file_name(level2_journal_base(database_file));
    return {database_file,
            ResultFile::partial_name(database_file),
            level1,
            ResultFile::partial_name(level1),
            level2,
            ResultFile::partial_name(level2)};
  }
} // namespace ddfem::coarsening
