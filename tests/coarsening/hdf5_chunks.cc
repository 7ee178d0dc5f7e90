// How the database files store datasets of every rank (hdf5::write_dataset).
// The database test (tests/coarsening/database.cc) checks the chunks of the
// 1-D lookup tables of a palette of five materials; the parameters of the
// entries are 3-D ({entries, points, 6}) and level 2's outgrow one chunk
// only with hundreds of entries, which no test builds. Here datasets of
// rank 1, 2 and 3 are written and read back directly:
// - the chunks hold whole rows, at most 1 MiB each (one row if a row is
//   larger), and share the rows evenly, so that they store at most one row
//   per chunk beyond the data: here, as for every dataset of the database
//   files (rows of at most 3 KiB), under 1 % more than its bytes;
// - what is read back is what was written, bit for bit;
// - a flipped bit in the last chunk fails the read (its Fletcher32
//   checksum), not only one in the first;
// - an empty dataset is written without chunks and reads back empty.

#include <hdf5.h>

#include <filesystem>
#include <fstream>

#include "../../source/coarsening/hdf5_io.h"
#include "../tests.h"

using namespace ddfem::coarsening;

namespace
{
  /// Writes a dataset of shape @p dims into @p file_name, reads it back
  /// and prints the chunk shape, the storage against the bytes, and whether
  /// the values came back bit for bit.
  template <typename T>
  void
  round_trip(const std::string &file_name, const std::vector<hsize_t> &dims)
  {
    std::size_t n = 1;
    for (const hsize_t d : dims)
      n *= d;
    std::vector<T> data(n);
    for (std::size_t i = 0; i < n; ++i)
      data[i] = T(i) + T(i) / T(8); // distinct, exact in either type
    {
      const hdf5::Handle file(
        H5Fcreate(file_name.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
        H5Fclose);
      hdf5::write_dataset(file, "group/data", dims, data);
    }
    const hdf5::Handle file(
      H5Fopen(file_name.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    const hdf5::Handle set(H5Dopen2(file, "group/data", H5P_DEFAULT), H5Dclose);
    const hdf5::Handle plist(H5Dget_create_plist(set), H5Pclose);
    std::cout << hdf5::describe(dims) << " of " << sizeof(T) << " bytes: ";
    if (H5Pget_layout(plist) == H5D_CHUNKED)
      {
        std::vector<hsize_t> chunk(dims.size());
        H5Pget_chunk(plist, chunk.size(), chunk.data());
        hsize_t n_chunks = 0;
        {
          const hdf5::Handle space(H5Dget_space(set), H5Sclose);
          H5Dget_num_chunks(set, space, &n_chunks);
        }
        const double bytes = double(n) * sizeof(T);
        std::cout << "chunks " << hdf5::describe(chunk) << " (" << n_chunks
                  << "), stored in at most 1 % more than the bytes: "
                  << (H5Dget_storage_size(set) <= 1.01 * bytes &&
                      H5Dget_storage_size(set) >= bytes);
      }
    else
      std::cout << "not chunked";
    const std::vector<T> read = hdf5::read_dataset<T>(file, "group/data", dims);
    std::cout << ", read back bit for bit: " << (read == data) << std::endl;
  }

  /// Flips a bit of the last chunk of the dataset in @p file_name and prints
  /// whether reading it fails.
  void
  flip_last_chunk(const std::string          &file_name,
                  const std::vector<hsize_t> &dims)
  {
    haddr_t address = HADDR_UNDEF;
    hsize_t size    = 0;
    {
      const hdf5::Handle file(
        H5Fopen(file_name.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
      const hdf5::Handle set(H5Dopen2(file, "group/data", H5P_DEFAULT),
                             H5Dclose);
      const hdf5::Handle space(H5Dget_space(set), H5Sclose);
      hsize_t            n_chunks = 0;
      H5Dget_num_chunks(set, space, &n_chunks);
      std::vector<hsize_t> offset(dims.size());
      unsigned int         mask = 0;
      AssertThrow(n_chunks > 1 && H5Dget_chunk_info(set,
                                                    space,
                                                    n_chunks - 1,
                                                    offset.data(),
                                                    &mask,
                                                    &address,
                                                    &size) >= 0,
                  dealii::ExcMessage("no last chunk to flip a bit in"));
    }
    {
      std::fstream data(file_name,
                        std::ios::in | std::ios::out | std::ios::binary);
      data.seekg(address + size / 2);
      const char byte = data.get() ^ 0x10;
      data.seekp(address + size / 2);
      data.put(byte);
    }
    const hdf5::Handle file(
      H5Fopen(file_name.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    try
      {
        hdf5::read_dataset<double>(file, "group/data", dims);
        std::cout << "  a flipped bit in the last chunk: READ WITHOUT ERROR"
                  << std::endl;
      }
    catch (const hdf5::FileProblem &problem)
      {
        std::cout << "  a flipped bit in the last chunk: " << problem.what
                  << std::endl;
      }
  }
} // namespace



int
main()
{
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); // the checks' messages only

  // Level-2 parameters: 700 entries of 64 points x 6 numbers, rows of
  // 3 KiB, 2.05 MiB in all: 341 rows would fill 1 MiB, so three chunks of
  // 234 rows (702, two rows to spare) instead of 341, 341 and a last one
  // of 18 rows stored as 341.
  const std::vector<hsize_t> level2 = {700, 64, 6};
  round_trip<double>("level2.h5", level2);
  flip_last_chunk("level2.h5", level2);

  // Level-1 parameters and fit errors of as many entries: one chunk each.
  round_trip<double>("level1.h5", {700, 8, 6});
  round_trip<double>("errors.h5", {700, 2});

  // A lookup table of 5^8 combinations: 1.49 MiB of int32 in two chunks.
  round_trip<std::int32_t>("lookup.h5", {390625});

  // Rows of 2.3 MiB: one row per chunk.
  round_trip<std::int64_t>("wide.h5", {3, 300000});

  // No entries yet (a database before its first fit).
  round_trip<double>("empty.h5", {0, 8, 6});
}
