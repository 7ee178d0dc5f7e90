#ifndef ddfem_coarsening_hdf5_io_h
#define ddfem_coarsening_hdf5_io_h

// Small helpers over the HDF5 C API for the database files (internal to
// the coarsening module): every failure becomes a message naming what is
// wrong, never an abort.

#include <deal.II/base/exceptions.h>

#include <ddfem/coarsening/database.h>
#include <hdf5.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace ddfem::coarsening::hdf5
{
  using namespace dealii;

  /// An HDF5 identifier closed by the matching function on scope exit.
  class Handle
  {
  public:
    /// Takes ownership of @p id (negative: invalid), closed by @p close.
    Handle(const hid_t id, herr_t (*close)(hid_t))
      : id(id)
      , close(close)
    {}
    /// Closes a valid identifier.
    ~Handle()
    {
      if (id >= 0)
        close(id);
    }
    /// Not copyable: one owner closes the identifier.
    Handle(const Handle &) = delete;
    /// Not copyable.
    Handle &
    operator=(const Handle &) = delete;
    /// The identifier, for the HDF5 calls.
    operator hid_t() const
    {
      return id;
    }
    /// Whether the call that made the identifier succeeded.
    bool
    valid() const
    {
      return id >= 0;
    }
    /**
     * Closes the identifier now and returns whether that succeeded. A file
     * written through HDF5 gets its metadata only when it is closed, so a
     * writer must check this (the destructor cannot report a failure).
     */
    bool
    close_now()
    {
      const bool closed = id >= 0 && close(id) >= 0;
      id                = -1;
      return closed;
    }

  private:
    hid_t id;
    herr_t (*close)(hid_t);
  };

  /// Thrown while reading and turned into a message naming the file.
  struct FileProblem
  {
    /// What is wrong, completing "The metamaterial database file 'F' ...".
    std::string what;
  };

  /**
   * Whether HDF5's error stack, that of the last call that failed, holds a
   * failure to lock a file: HDF5 locks a file it opens, so another program
   * has it open for writing, or the file system refuses locks.
   */
  inline bool
  lock_failed()
  {
    bool locked = false;
    H5Ewalk2(
      H5E_DEFAULT,
      H5E_WALK_UPWARD,
      [](unsigned int, const H5E_error2_t *error, void *data) -> herr_t {
        if (error->min_num == H5E_CANTLOCKFILE)
          *static_cast<bool *>(data) = true;
        return 0;
      },
      &locked);
    return locked;
  }

  /// Throws FileProblem{@p what} unless @p condition holds.
  inline void
  check(const bool condition, const std::string &what)
  {
    if (!condition)
      throw FileProblem{what};
  }

  /// The HDF5 memory type of @p T (double and fixed-width integers).
  template <typename T>
  hid_t
  native_type();
  template <>
  inline hid_t
  native_type<double>()
  {
    return H5T_NATIVE_DOUBLE;
  }
  template <>
  inline hid_t
  native_type<std::int64_t>()
  {
    return H5T_NATIVE_INT64;
  }
  template <>
  inline hid_t
  native_type<std::int32_t>()
  {
    return H5T_NATIVE_INT32;
  }
  template <>
  inline hid_t
  native_type<std::uint8_t>()
  {
    return H5T_NATIVE_UINT8;
  }

  /**
   * Writes @p data as the dataset @p name of shape @p dims, creating
   * intermediate groups. A dataset with elements is stored in as few
   * chunks of whole rows as keep each within about 1 MiB (one row if a row
   * is larger), all of one size, so that the last lacks fewer rows than
   * there are chunks; each has a Fletcher32 checksum, which HDF5 verifies
   * whenever it reads the chunk: a flipped bit in a parameter or a table
   * fails the read instead of loading as another valid number. The dataset
   * is closed here, which writes its chunks, so that a write that fails (a
   * full disk) is an error naming it.
   */
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
    // Should this fail, H5Dcreate2() does below for a name in a group.
    H5Pset_create_intermediate_group(lcpl, 1);
    std::size_t n_elements = 1;
    for (const hsize_t d : dims)
      n_elements *= d;
    Assert(n_elements == data.size(),
           ExcDimensionMismatch(n_elements, data.size()));
    const Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
    // No modification times: a file's bytes depend on its contents only.
    AssertThrow(H5Pset_obj_track_times(dcpl, false) >= 0,
                ExcMessage("Could not write the dataset '" + name + "'."));
    if (!dims.empty() && n_elements > 0)
      {
        std::vector<hsize_t> chunk = dims;
        hsize_t              row   = sizeof(T);
        for (std::size_t d = 1; d < dims.size(); ++d)
          row *= dims[d];
        // The rows spread evenly over the chunks: HDF5 stores the last
        // chunk whole, however few rows of the dataset it holds (level 2's
        // 1200 KiB of parameters took 2 MiB in chunks of 1 MiB).
        const hsize_t most =
          std::clamp<hsize_t>((hsize_t(1) << 20) / row, 1, dims[0]);
        const hsize_t n_chunks = (dims[0] + most - 1) / most;
        chunk[0]               = (dims[0] + n_chunks - 1) / n_chunks;
        AssertThrow(H5Pset_chunk(dcpl, chunk.size(), chunk.data()) >= 0 &&
                      H5Pset_fletcher32(dcpl) >= 0,
                    ExcMessage("Could not set up the checksums of the "
                               "dataset '" +
                               name + "'."));
      }
    Handle set(
      H5Dcreate2(
        file, name.c_str(), native_type<T>(), space, lcpl, dcpl, H5P_DEFAULT),
      H5Dclose);
    AssertThrow(set.valid() &&
                  (data.empty() || H5Dwrite(set,
                                            native_type<T>(),
                                            H5S_ALL,
                                            H5S_ALL,
                                            H5P_DEFAULT,
                                            data.data()) >= 0) &&
                  set.close_now(),
                ExcMessage("Could not write the dataset '" + name + "'."));
  }

  /// The extents @p extents as text ("3 x 8 x 6").
  inline std::string
  describe(const std::vector<hsize_t> &extents)
  {
    std::ostringstream text;
    for (std::size_t i = 0; i < extents.size(); ++i)
      text << (i == 0 ? "" : " x ") << extents[i];
    return text.str();
  }

  /**
   * The shape of the open dataset @p set named @p name. Throws FileProblem
   * if it cannot be read or has more elements than the dataset stores (a
   * corrupt header), so callers may allocate for it, and if a chunk is
   * larger than the dataset, missing from its index, or marked to skip
   * its filters.
   */
  inline std::vector<hsize_t>
  dataset_shape(const hid_t set, const std::string &name)
  {
    const Handle space(H5Dget_space(set), H5Sclose);
    const int    rank = space.valid() ? H5Sget_simple_extent_ndims(space) : -1;
    check(rank >= 0 && rank <= H5S_MAX_RANK,
          "has the dataset '" + name + "' with an unreadable shape");
    std::vector<hsize_t> shape(rank), most_shape(rank);
    check(H5Sget_simple_extent_dims(space, shape.data(), most_shape.data()) ==
            rank,
          "has the dataset '" + name + "' with an unreadable shape");
    // The elements the dataset stores bound those of its shape, whose
    // product is checked factor by factor so that it cannot overflow. A
    // dataset with a filter other than the checksum may be compressed
    // (h5repack -f GZIP): deflate stores at least one byte per 1032.
    const Handle type(H5Dget_type(set), H5Tclose);
    const Handle creation(H5Dget_create_plist(set), H5Pclose);
    const int    n_filters = creation.valid() ? H5Pget_nfilters(creation) : -1;
    check(type.valid() && n_filters >= 0,
          "has the dataset '" + name + "' with unreadable properties");
    bool filtered = false;
    for (int f = 0; f < n_filters; ++f)
      {
        unsigned int flags    = 0;
        std::size_t  n_values = 0;
        filtered =
          filtered ||
          H5Pget_filter2(
            creation, f, &flags, &n_values, nullptr, 0, nullptr, nullptr) !=
            H5Z_FILTER_FLETCHER32;
      }
    const std::size_t size   = H5Tget_size(type);
    const hsize_t     bytes  = H5Dget_storage_size(set);
    const hsize_t     most   = std::numeric_limits<hsize_t>::max();
    hsize_t           stored = size > 0 ? bytes / size : 0;
    if (filtered)
      stored = stored > most / 1032 ? most : 1032 * stored;
    hsize_t n = 1;
    for (const hsize_t d : shape)
      {
        check(d == 0 || n <= stored / d,
              "has the dataset '" + name + "' of shape " + describe(shape) +
                ", more elements than the " + std::to_string(bytes) +
                " bytes it stores can hold (corrupt file" +
                (filtered ? ", or compressed beyond gzip's ratio?)" : "?)"));
        n *= d;
      }
    // HDF5 reads a dataset chunk by chunk and trusts the chunks' shape: one
    // larger than the dataset's largest extent (a damaged byte in its
    // header; ddfem's and h5repack's are not) made it copy past its buffer.
    if (H5Pget_layout(creation) == H5D_CHUNKED)
      {
        std::vector<hsize_t> chunk(H5S_MAX_RANK);
        bool ok = H5Pget_chunk(creation, H5S_MAX_RANK, chunk.data()) == rank;
        for (int d = 0; ok && d < rank; ++d)
          ok = chunk[d] >= 1 && chunk[d] <= std::max<hsize_t>(most_shape[d], 1);
        chunk.resize(std::max(rank, 0));
        check(ok,
              "has the dataset '" + name + "' of shape " + describe(shape) +
                " with a corrupt chunk layout (chunks of " + describe(chunk) +
                ")");
        // Every chunk is written (write_dataset()), with all its filters.
        // HDF5 reads one its index does not find, a damaged byte there, as
        // never written: as zeros, and without a checksum to fail. It skips
        // the filters a chunk's mask names, a damaged mask the checksum too.
        std::vector<hsize_t> origin(rank, 0);
        for (bool more = n > 0; more;)
          {
            unsigned int mask    = 0;
            haddr_t      address = HADDR_UNDEF;
            hsize_t      size    = 0;
            const bool   found   = H5Dget_chunk_info_by_coord(set,
                                                          origin.data(),
                                                          &mask,
                                                          &address,
                                                          &size) >= 0 &&
                               address != HADDR_UNDEF;
            if (!found || mask != 0)
              {
                std::string at;
                for (const hsize_t i : origin)
                  at += (at.empty() ? "" : ", ") + std::to_string(i);
                throw FileProblem{"has the dataset '" + name + "' " +
                                  (found ?
                                     "with filters skipped on its chunk at (" :
                                     "without its chunk at (") +
                                  at + ") (a corrupt chunk index?)"};
              }
            more = false;
            for (int d = rank - 1; d >= 0 && !more; --d)
              {
                origin[d] += chunk[d];
                more = origin[d] < shape[d];
                if (!more)
                  origin[d] = 0;
              }
          }
      }
    return shape;
  }

  /// Reads a dataset whose shape must be @p dims and whose stored element
  /// type must be @p T's, as write_dataset() stores it.
  template <typename T>
  std::vector<T>
  read_dataset(const hid_t                 file,
               const std::string          &name,
               const std::vector<hsize_t> &dims)
  {
    check(H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0,
          "has no dataset '" + name + "'");
    const Handle set(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose);
    check(set.valid(), "cannot open the dataset '" + name + "'");
    const std::vector<hsize_t> shape = dataset_shape(set, name);
    check(shape == dims,
          "has the dataset '" + name + "' of shape " + describe(shape) +
            " instead of " + describe(dims));
    // HDF5 would convert another stored type, which the header names
    // without a checksum: a damaged exponent bias would scale every value.
    const Handle type(H5Dget_type(set), H5Tclose);
    check(type.valid() && H5Tequal(type, native_type<T>()) > 0,
          "has the dataset '" + name +
            "' stored with another element type than the one ddfem writes "
            "(corrupt file?)");
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
          "cannot read the dataset '" + name + "'" +
            " (a truncated file, or corrupt data that fail their checksum?)");
    return data;
  }

  /// Writes the string attribute @p name of @p file (or group).
  inline void
  write_attribute(const hid_t        file,
                  const std::string &name,
                  const std::string &value)
  {
    const Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
    AssertThrow(H5Tset_size(type, std::max<std::size_t>(1, value.size())) >= 0,
                ExcMessage("Could not write the attribute '" + name + "'."));
    const Handle space(H5Screate(H5S_SCALAR), H5Sclose);
    const Handle attribute(
      H5Acreate2(file, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT),
      H5Aclose);
    AssertThrow(attribute.valid() &&
                  H5Awrite(attribute, type, value.c_str()) >= 0,
                ExcMessage("Could not write the attribute '" + name + "'."));
  }

  /**
   * Reads the string attribute @p name. Throws FileProblem if it is
   * missing, not one fixed-length string (an array of them would overrun
   * the buffer), or holds other than printable ASCII text, tabs and line
   * breaks, which is all that ddfem writes (attributes carry no checksum:
   * a damaged byte would otherwise reach a message).
   */
  inline std::string
  read_attribute(const hid_t file, const std::string &name)
  {
    check(H5Aexists(file, name.c_str()) > 0, "has no attribute " + name);
    const Handle attribute(H5Aopen(file, name.c_str(), H5P_DEFAULT), H5Aclose);
    const Handle type(H5Aget_type(attribute), H5Tclose);
    const Handle space(H5Aget_space(attribute), H5Sclose);
    check(attribute.valid() && type.valid() && space.valid() &&
            H5Tget_class(type) == H5T_STRING && H5Tis_variable_str(type) == 0 &&
            H5Sget_simple_extent_npoints(space) == 1,
          "has an attribute '" + name + "' that is not a single string");
    // One byte more than stored, for the terminator: a string that fills
    // its size (as ddfem writes them, or padded by another tool) is read
    // whole.
    std::string  value(H5Tget_size(type) + 1, '\0');
    const Handle memory(H5Tcopy(H5T_C_S1), H5Tclose);
    check(H5Tset_size(memory, value.size()) >= 0 &&
            H5Aread(attribute, memory, value.data()) >= 0,
          "cannot read the attribute " + name);
    value.erase(std::min(value.size(), value.find('\0')));
    check(std::all_of(value.begin(),
                      value.end(),
                      [](const char c) {
                        return (c >= 0x20 && c < 0x7F) || c == '\t' ||
                               c == '\n';
                      }),
          "has an attribute '" + name +
            "' with bytes that are not text (corrupt file?)");
    return value;
  }
  /// Reads the string attribute @p name as a finite number (FileProblem
  /// naming the attribute and its text if it is not one).
  inline double
  read_number_attribute(const hid_t file, const std::string &name)
  {
    const std::string  text = read_attribute(file, name);
    std::istringstream in(text);
    double             value = 0;
    in >> value;
    check(!text.empty() && !in.fail() && in.eof() && std::isfinite(value),
          "has an invalid '" + name + "' attribute '" + text + "'");
    return value;
  }

  /// Number of values stored per metamaterial point: mu, lambda, C, v.
  constexpr unsigned int n_values = 6;

  /// A material record from its n_values stored numbers.
  material::MaterialPoint
  point_from(const double *values);

  /**
   * Whether a stored material record is physical: finite, mu > 0,
   * lambda >= 0, C >= 0 and a unit direction. The fits guarantee it; the
   * readers of files and journals check it.
   */
  bool
  is_physical(const material::MaterialPoint &p);

  /**
   * Appends to @p m the @p n_points points whose n_values stored numbers
   * each follow one another from @p values, up to the first that is not
   * physical, and returns that point's index (@p n_points if there is none).
   */
  unsigned int
  append_points(const double      *values,
                const unsigned int n_points,
                Metamaterial      &m);

  /**
   * Sets the fit statistics of @p entry from their @p stored values: median
   * and largest error, smallest and largest strain, samples kept and
   * dropped. Returns false, and leaves @p entry unchanged, where they cannot
   * be an entry's: errors that are not finite or negative or a median above
   * the largest, strains that are not finite or whose range is reversed, or
   * counts that are not whole numbers that fit into Entry's.
   */
  bool
  set_statistics(const std::array<double, 6> &stored, Entry &entry);

  /// Appends the n_values stored numbers of every point of @p m to @p values.
  void
  append_values(const Metamaterial &m, std::vector<double> &values);

  /**
   * Writes metamaterial entries of @p n_points points into @p group, with
   * their child fits (Entry::child_material) if @p with_children.
   */
  void
  write_entries(const hid_t               file,
                const std::string        &group,
                const std::vector<Entry> &entries,
                const unsigned int        n_points,
                const bool                with_children);

  /// Reads and validates the entries of @p group (FileProblem if bad),
  /// with their child fits if @p with_children.
  std::vector<Entry>
  read_entries(const hid_t        file,
               const std::string &group,
               const unsigned int n_points,
               const bool         with_children);

  /// The first dimension of dataset @p name (FileProblem if missing).
  hsize_t
  dataset_length(const hid_t file, const std::string &name);
} // namespace ddfem::coarsening::hdf5

#endif
