#include <deal.II/base/exceptions.h>

#include <ddfem/coarsening/database.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>

namespace ddfem::coarsening
{
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



  std::string
  DatabaseSettings::fingerprint() const
  {
    std::ostringstream s;
    s << std::setprecision(17) << "palette: " << palette
      << " | void: " << with_void
      << " | force patterns: " << sampling.n_directions
      << ", magnitudes: " << sampling.n_magnitudes
      << ", strains: " << sampling.min_strain << "-" << sampling.max_strain
      << ", traction gradient: " << sampling.traction_gradient
      << ", stretch directions: " << sampling.n_stretch_directions
      << " | regularization: " << fitting.regularization
      << ", stiffness floor: " << fitting.stiffness_floor
      << ", held-out every: " << fitting.held_out_every;
    return s.str();
  }



  namespace
  {
    constexpr unsigned int n_values = 6; // mu, lambda, C, v

    unsigned int
    count_materials(const std::string &palette)
    {
      return std::count(palette.begin(), palette.end(), ';') + 1;
    }

    /// An HDF5 identifier closed by the matching function on scope exit.
    class Handle
    {
    public:
      Handle(const hid_t id, herr_t (*close)(hid_t))
        : id(id)
        , close(close)
      {}
      ~Handle()
      {
        if (id >= 0)
          close(id);
      }
      Handle(const Handle &) = delete;
      Handle &
      operator=(const Handle &) = delete;
      operator hid_t() const
      {
        return id;
      }
      bool
      valid() const
      {
        return id >= 0;
      }

    private:
      hid_t id;
      herr_t (*close)(hid_t);
    };

    /// Thrown inside load() and turned into a message naming the file.
    struct FileProblem
    {
      std::string what;
    };

    void
    check(const bool condition, const std::string &what)
    {
      if (!condition)
        throw FileProblem{what};
    }

    template <typename T>
    hid_t
    native_type();
    template <>
    hid_t
    native_type<double>()
    {
      return H5T_NATIVE_DOUBLE;
    }
    template <>
    hid_t
    native_type<std::int64_t>()
    {
      return H5T_NATIVE_INT64;
    }
    template <>
    hid_t
    native_type<std::int32_t>()
    {
      return H5T_NATIVE_INT32;
    }
    template <>
    hid_t
    native_type<std::uint8_t>()
    {
      return H5T_NATIVE_UINT8;
    }

    template <typename T>
    void
    write_dataset(const hid_t                 file,
                  const std::string          &name,
                  const std::vector<hsize_t> &dims,
                  const std::vector<T>       &data)
    {
      const Handle space(H5Screate_simple(dims.size(), dims.data(), nullptr),
                         H5Sclose);
      const Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
      H5Pset_create_intermediate_group(lcpl, 1);
      const Handle set(H5Dcreate2(file,
                                  name.c_str(),
                                  native_type<T>(),
                                  space,
                                  lcpl,
                                  H5P_DEFAULT,
                                  H5P_DEFAULT),
                       H5Dclose);
      AssertThrow(set.valid() && (data.empty() || H5Dwrite(set,
                                                           native_type<T>(),
                                                           H5S_ALL,
                                                           H5S_ALL,
                                                           H5P_DEFAULT,
                                                           data.data()) >= 0),
                  ExcMessage("Could not write the dataset " + name + "."));
    }

    /// Reads a dataset whose shape must be @p dims.
    template <typename T>
    std::vector<T>
    read_dataset(const hid_t                 file,
                 const std::string          &name,
                 const std::vector<hsize_t> &dims)
    {
      check(H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0,
            "the dataset " + name + " is missing");
      const Handle set(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose);
      check(set.valid(), "the dataset " + name + " cannot be opened");
      const Handle         space(H5Dget_space(set), H5Sclose);
      std::vector<hsize_t> shape(H5Sget_simple_extent_ndims(space));
      H5Sget_simple_extent_dims(space, shape.data(), nullptr);
      std::ostringstream expected, found;
      for (const auto d : dims)
        expected << (&d == dims.data() ? "" : " x ") << d;
      for (const auto d : shape)
        found << (&d == shape.data() ? "" : " x ") << d;
      check(shape == dims,
            "the dataset " + name + " has shape " + found.str() +
              " instead of " + expected.str());
      std::size_t n = 1;
      for (const auto d : dims)
        n *= d;
      std::vector<T> data(n);
      check(n == 0 || H5Dread(set,
                              native_type<T>(),
                              H5S_ALL,
                              H5S_ALL,
                              H5P_DEFAULT,
                              data.data()) >= 0,
            "the dataset " + name + " cannot be read (truncated file?)");
      return data;
    }

    void
    write_attribute(const hid_t        file,
                    const std::string &name,
                    const std::string &value)
    {
      const Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
      H5Tset_size(type, std::max<std::size_t>(1, value.size()));
      const Handle space(H5Screate(H5S_SCALAR), H5Sclose);
      const Handle attribute(
        H5Acreate2(file, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT),
        H5Aclose);
      AssertThrow(attribute.valid() &&
                    H5Awrite(attribute, type, value.c_str()) >= 0,
                  ExcMessage("Could not write the attribute " + name + "."));
    }

    std::string
    read_attribute(const hid_t file, const std::string &name)
    {
      check(H5Aexists(file, name.c_str()) > 0,
            "the attribute " + name + " is missing");
      const Handle attribute(H5Aopen(file, name.c_str(), H5P_DEFAULT),
                             H5Aclose);
      const Handle type(H5Aget_type(attribute), H5Tclose);
      check(attribute.valid() && H5Tget_class(type) == H5T_STRING,
            "the attribute " + name + " is not a string");
      std::string  value(H5Tget_size(type), '\0');
      const Handle memory(H5Tcopy(H5T_C_S1), H5Tclose);
      H5Tset_size(memory, value.size());
      check(H5Aread(attribute, memory, value.data()) >= 0,
            "the attribute " + name + " cannot be read");
      return value.substr(0, value.find('\0'));
    }
  } // namespace



  Database::Database(const DatabaseSettings &settings,
                     const unsigned int      n_materials)
    : palette_description(settings.palette)
    , settings_fingerprint(settings.fingerprint())
    , index(n_materials, settings.with_void)
    , entry_of(index.size(), -1)
    , symmetry_of(index.size(), 0)
  {}



  bool
  Database::contains(const Combination &c) const
  {
    return index.contains(c) && entry_of[index.key(c)] >= 0;
  }



  Metamaterial
  Database::lookup(const Combination &c) const
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
    const std::size_t key = index.key(c);
    return transform(fitted[entry_of[key]].material, group, symmetry_of[key]);
  }



  std::vector<Combination>
  Database::missing(const std::vector<Combination> &combinations) const
  {
    std::vector<Combination> result;
    for (const Combination &c : combinations)
      AssertThrow(index.contains(c),
                  ExcMessage("A block has a material id the metamaterial "
                             "database does not cover (void, with a database "
                             "built with Database/Include void = false, or "
                             "an id above the palette's size)."));
    for (const Combination &c : combinations)
      if (std::any_of(c.begin(), c.end(), [](auto id) { return id != 0; }) &&
          !contains(c))
        result.push_back(group.canonical(c).first);
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
    if (entry_of[entry.key] >= 0)
      return;
    // Keep the entries sorted by key: the file does not depend on the
    // order in which threads finish.
    const auto position =
      std::lower_bound(fitted.begin(),
                       fitted.end(),
                       entry.key,
                       [](const Entry &e, const std::size_t key) {
                         return e.key < key;
                       });
    const int new_index = position - fitted.begin();
    fitted.insert(position, entry);
    for (auto &e : entry_of)
      if (e >= new_index)
        ++e;
    for (unsigned int g = 0; g < CubeSymmetries::size; ++g)
      {
        const std::size_t key = index.key(group.apply(g, representative));
        if (entry_of[key] < 0)
          {
            entry_of[key]    = new_index;
            symmetry_of[key] = g;
          }
      }
  }



  void
  Database::save(const std::string &file) const
  {
    const std::string temporary = file + ".partial";
    {
      const Handle h5(
        H5Fcreate(temporary.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
        H5Fclose);
      AssertThrow(h5.valid(),
                  ExcMessage("Cannot create the database file " + temporary +
                             " (does its directory exist and is it "
                             "writable?)."));
      write_attribute(h5, "format", "ddfem metamaterial database");
      write_attribute(h5,
                      "format version",
                      std::to_string(database_format_version));
      write_attribute(h5, "code version", "ddfem 0.1");
      write_attribute(h5, "palette", palette_description);
      write_attribute(h5, "with void", index.with_void() ? "1" : "0");
      write_attribute(h5, "settings", settings_fingerprint);
      write_attribute(h5, "representatives", std::to_string(representatives));

      const hsize_t             n = fitted.size();
      std::vector<std::int64_t> keys, counts;
      std::vector<double>       parameters, errors, strains;
      for (const Entry &e : fitted)
        {
          keys.push_back(e.key);
          for (const auto &p : e.material.points)
            for (const double value : {p.mu,
                                       p.lambda,
                                       p.anisotropy,
                                       p.direction[0],
                                       p.direction[1],
                                       p.direction[2]})
              parameters.push_back(value);
          errors.insert(errors.end(), {e.median_error, e.max_error});
          strains.insert(strains.end(), {e.min_strain, e.max_strain});
          counts.insert(counts.end(), {e.n_samples, e.n_dropped});
        }
      write_dataset(h5, "entries/key", {n}, keys);
      write_dataset(h5, "entries/parameters", {n, 8, n_values}, parameters);
      write_dataset(h5, "entries/fit error", {n, 2}, errors);
      write_dataset(h5, "entries/strain range", {n, 2}, strains);
      write_dataset(h5, "entries/samples", {n, 2}, counts);
      write_dataset(h5, "lookup/entry", {hsize_t(index.size())}, entry_of);
      write_dataset(h5,
                    "lookup/symmetry",
                    {hsize_t(index.size())},
                    symmetry_of);
    }
    std::filesystem::rename(temporary, file);
  }



  Database
  Database::load(const std::string &file)
  {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    const std::string where = "The metamaterial database file '" + file + "' ";
    AssertThrow(std::filesystem::exists(file),
                ExcMessage(where + "does not exist."));
    try
      {
        check(H5Fis_hdf5(file.c_str()) > 0,
              "is not an HDF5 file (corrupt or truncated?)");
        const Handle h5(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT),
                        H5Fclose);
        check(h5.valid(), "cannot be opened (corrupt or truncated?)");
        check(read_attribute(h5, "format") == "ddfem metamaterial database",
              "is not a ddfem metamaterial database");
        const std::string version = read_attribute(h5, "format version");
        check(version == std::to_string(database_format_version),
              "has format version " + version + ", this program reads " +
                std::to_string(database_format_version));

        DatabaseSettings settings;
        settings.palette              = read_attribute(h5, "palette");
        settings.with_void            = read_attribute(h5, "with void") == "1";
        const std::string fingerprint = read_attribute(h5, "settings");
        Database          db(settings, count_materials(settings.palette));
        db.settings_fingerprint = fingerprint;
        db.representatives = std::stoul(read_attribute(h5, "representatives"));

        const Handle keys_set(H5Dopen2(h5, "entries/key", H5P_DEFAULT),
                              H5Dclose);
        check(keys_set.valid(), "has no dataset entries/key");
        const Handle space(H5Dget_space(keys_set), H5Sclose);
        hsize_t      n = 0;
        check(H5Sget_simple_extent_ndims(space) == 1,
              "has a dataset entries/key that is not a list");
        H5Sget_simple_extent_dims(space, &n, nullptr);

        const auto keys = read_dataset<std::int64_t>(h5, "entries/key", {n});
        const auto parameters =
          read_dataset<double>(h5, "entries/parameters", {n, 8, n_values});
        const auto errors =
          read_dataset<double>(h5, "entries/fit error", {n, 2});
        const auto strains =
          read_dataset<double>(h5, "entries/strain range", {n, 2});
        const auto counts =
          read_dataset<std::int64_t>(h5, "entries/samples", {n, 2});
        const hsize_t n_keys = db.index.size();
        db.entry_of = read_dataset<std::int32_t>(h5, "lookup/entry", {n_keys});
        db.symmetry_of =
          read_dataset<std::uint8_t>(h5, "lookup/symmetry", {n_keys});

        for (hsize_t e = 0; e < n; ++e)
          {
            Entry entry;
            check(keys[e] >= 0 && std::size_t(keys[e]) < n_keys &&
                    (e == 0 || keys[e] > keys[e - 1]),
                  "has an invalid entry key at entry " + std::to_string(e));
            entry.key = keys[e];
            for (unsigned int q = 0; q < 8; ++q)
              {
                const double           *v = &parameters[(e * 8 + q) * n_values];
                material::MaterialPoint p;
                p.mu         = v[0];
                p.lambda     = v[1];
                p.anisotropy = v[2];
                for (unsigned int d = 0; d < 3; ++d)
                  p.direction[d] = v[3 + d];
                check(std::isfinite(p.mu) && p.mu > 0 &&
                        std::isfinite(p.lambda) && p.lambda >= 0 &&
                        std::isfinite(p.anisotropy) && p.anisotropy >= 0 &&
                        std::abs(p.direction.norm() - 1) < 1e-6,
                      "has non-physical parameters at entry " +
                        std::to_string(e) + ", point " + std::to_string(q));
                entry.material.points.push_back(p);
              }
            entry.median_error = errors[2 * e];
            entry.max_error    = errors[2 * e + 1];
            entry.min_strain   = strains[2 * e];
            entry.max_strain   = strains[2 * e + 1];
            entry.n_samples    = counts[2 * e];
            entry.n_dropped    = counts[2 * e + 1];
            db.fitted.push_back(entry);
          }
        for (std::size_t k = 0; k < n_keys; ++k)
          check(db.entry_of[k] >= -1 && db.entry_of[k] < std::int64_t(n) &&
                  db.symmetry_of[k] < CubeSymmetries::size,
                "has an invalid lookup table at combination " +
                  std::to_string(k));
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
                          const unsigned int                      first)
  {
    const auto distance = [&points](const unsigned int a,
                                    const unsigned int b) {
      double d = 0;
      for (unsigned int i = 0; i < points[a].size(); ++i)
        d += (points[a][i] - points[b][i]) * (points[a][i] - points[b][i]);
      return std::sqrt(d);
    };
    std::vector<unsigned int> picked = {first};
    std::vector<double>       nearest(points.size());
    for (unsigned int p = 0; p < points.size(); ++p)
      nearest[p] = distance(p, first);
    while (picked.size() < std::min<std::size_t>(k, points.size()))
      {
        const unsigned int next =
          std::max_element(nearest.begin(), nearest.end()) - nearest.begin();
        picked.push_back(next);
        for (unsigned int p = 0; p < points.size(); ++p)
          nearest[p] = std::min(nearest[p], distance(p, next));
      }
    return picked;
  }



  std::vector<CornerDisplacements>
  feature_deformations(const CoarseElement &element,
                       const unsigned int   n,
                       const double         strain,
                       const std::uint64_t  seed)
  {
    std::mt19937_64                  generator(seed);
    std::normal_distribution<double> normal;
    std::vector<CornerDisplacements> result;
    std::vector<Tensor<2, 3>>        F;
    while (result.size() < n)
      {
        CornerDisplacements u;
        for (auto &corner : u)
          for (unsigned int d = 0; d < 3; ++d)
            corner[d] = normal(generator);
        element.deformation_gradients(u, F);
        double largest = 0;
        for (const auto &Fq : F)
          for (const double e :
               eigenvalues(symmetrize(Fq - unit_symmetric_tensor<3>())))
            largest = std::max(largest, std::abs(e));
        for (auto &corner : u)
          corner *= strain / largest;
        result.push_back(u);
      }
    return result;
  }



  void
  Database::compress(const unsigned int                      k,
                     const CoarseElement                    &element,
                     const std::vector<CornerDisplacements> &deformations)
  {
    AssertThrow(k > 0,
                ExcMessage("Compression needs at least one "
                           "representative."));
    std::vector<std::vector<double>> features(index.size());
    std::vector<std::size_t>         keys;
    for (std::size_t key = 0; key < index.size(); ++key)
      {
        const Combination c = index.combination(key);
        if (std::all_of(c.begin(), c.end(), [](auto id) { return id == 0; }))
          continue;
        AssertThrow(entry_of[key] >= 0,
                    ExcMessage("Only a complete database can be compressed: "
                               "build it with Scope = all first."));
        const Metamaterial m = lookup(c);
        for (const auto &u : deformations)
          {
            double energy;
            AssertThrow(element.energy(u, m, energy) && energy > 0,
                        ExcInternalError());
            features[keys.size()].push_back(std::log(energy));
          }
        keys.push_back(key);
      }
    features.resize(keys.size());

    std::mt19937_64    generator(20260101);
    const unsigned int first =
      std::uniform_int_distribution<std::size_t>(0, keys.size() - 1)(generator);
    const std::vector<unsigned int> picked =
      farthest_point_sampling(features, k, first);

    // Redirect every combination to its nearest representative.
    std::vector<std::int32_t> new_entry_of(index.size(), -1);
    std::vector<std::uint8_t> new_symmetry_of(index.size(), 0);
    for (unsigned int p = 0; p < keys.size(); ++p)
      {
        unsigned int best          = 0;
        double       best_distance = std::numeric_limits<double>::max();
        for (unsigned int r = 0; r < picked.size(); ++r)
          {
            double d = 0;
            for (unsigned int i = 0; i < features[p].size(); ++i)
              d += std::pow(features[p][i] - features[picked[r]][i], 2);
            if (d < best_distance)
              {
                best_distance = d;
                best          = r;
              }
          }
        new_entry_of[keys[p]]    = entry_of[keys[picked[best]]];
        new_symmetry_of[keys[p]] = symmetry_of[keys[picked[best]]];
      }

    // Drop the entries nobody uses.
    std::vector<std::int32_t> renumber(fitted.size(), -1);
    std::vector<Entry>        kept;
    for (auto &e : new_entry_of)
      if (e >= 0)
        {
          if (renumber[e] < 0)
            renumber[e] = 0;
        }
    for (unsigned int e = 0; e < fitted.size(); ++e)
      if (renumber[e] == 0)
        {
          renumber[e] = kept.size();
          kept.push_back(fitted[e]);
        }
    for (auto &e : new_entry_of)
      if (e >= 0)
        e = renumber[e];
    fitted          = kept;
    entry_of        = new_entry_of;
    symmetry_of     = new_symmetry_of;
    representatives = picked.size();
  }



  namespace
  {
    constexpr std::uint32_t record_magic = 0x4444464dU; // "DDFM"

    /// FNV-1a over a byte range.
    std::uint64_t
    checksum(const std::vector<double> &values)
    {
      std::uint64_t h = 1469598103934665603ULL;
      const auto   *bytes =
        reinterpret_cast<const unsigned char *>(values.data());
      for (std::size_t i = 0; i < values.size() * sizeof(double); ++i)
        h = (h ^ bytes[i]) * 1099511628211ULL;
      return h;
    }

    std::string
    journal_name(const std::string &database_file)
    {
      return database_file + ".journal";
    }
  } // namespace



  Journal::Journal(const std::string &database_file,
                   const std::string &fingerprint)
  {
    const std::string name  = journal_name(database_file);
    const bool        fresh = !std::filesystem::exists(name);
    file                    = std::fopen(name.c_str(), "ab");
    AssertThrow(file != nullptr,
                ExcMessage("Cannot write the build journal " + name + "."));
    if (fresh)
      {
        const std::uint64_t length = fingerprint.size();
        std::fwrite(&length, sizeof(length), 1, file);
        std::fwrite(fingerprint.data(), 1, length, file);
        std::fflush(file);
      }
  }



  Journal::~Journal()
  {
    std::fclose(file);
  }



  void
  Journal::append(const Entry &entry)
  {
    std::vector<double> values = {double(entry.key),
                                  entry.median_error,
                                  entry.max_error,
                                  entry.min_strain,
                                  entry.max_strain,
                                  double(entry.n_samples),
                                  double(entry.n_dropped)};
    for (const auto &p : entry.material.points)
      values.insert(values.end(),
                    {p.mu,
                     p.lambda,
                     p.anisotropy,
                     p.direction[0],
                     p.direction[1],
                     p.direction[2]});
    const std::uint64_t sum = checksum(values);
    std::fwrite(&record_magic, sizeof(record_magic), 1, file);
    std::fwrite(values.data(), sizeof(double), values.size(), file);
    std::fwrite(&sum, sizeof(sum), 1, file);
    std::fflush(file);
  }



  std::vector<Entry>
  Journal::read(const std::string &database_file,
                const std::string &fingerprint)
  {
    std::vector<Entry> entries;
    const std::string  name = journal_name(database_file);
    std::FILE         *in   = std::fopen(name.c_str(), "rb");
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
        AssertThrow(false,
                    ExcMessage("The build journal " + name +
                               " belongs to a build with other settings (" +
                               stored +
                               "). Delete it or restore those "
                               "settings."));
      }
    std::vector<double> values(7 + 8 * n_values);
    std::uint32_t       magic;
    std::uint64_t       sum;
    while (std::fread(&magic, sizeof(magic), 1, in) == 1 &&
           magic == record_magic &&
           std::fread(values.data(), sizeof(double), values.size(), in) ==
             values.size() &&
           std::fread(&sum, sizeof(sum), 1, in) == 1 && sum == checksum(values))
      {
        Entry e;
        e.key          = values[0];
        e.median_error = values[1];
        e.max_error    = values[2];
        e.min_strain   = values[3];
        e.max_strain   = values[4];
        e.n_samples    = values[5];
        e.n_dropped    = values[6];
        for (unsigned int q = 0; q < 8; ++q)
          {
            const double           *v = &values[7 + q * n_values];
            material::MaterialPoint p;
            p.mu         = v[0];
            p.lambda     = v[1];
            p.anisotropy = v[2];
            for (unsigned int d = 0; d < 3; ++d)
              p.direction[d] = v[3 + d];
            e.material.points.push_back(p);
          }
        entries.push_back(e);
      }
    std::fclose(in);
    return entries;
  }



  void
  Journal::remove(const std::string &database_file)
  {
    std::filesystem::remove(journal_name(database_file));
  }
} // namespace ddfem::coarsening
