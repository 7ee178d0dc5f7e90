#ifndef ddfem_base_files_h
#define ddfem_base_files_h

#include <deal.II/base/exceptions.h>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <string>
#include <system_error>
#include <vector>

namespace ddfem
{
  namespace internal
  {
    /**
     * "Cannot create the directory ..." for @p path from parameter
     * @p where, or, where @p error says that a component's symbolic links
     * form a loop (found by looking, not by making it), that the path
     * cannot be followed.
     */
    inline dealii::ExcMessage
    directory_error(const std::string     &path,
                    const std::string     &where,
                    const std::error_code &error)
    {
      if (error == std::errc::too_many_symbolic_link_levels)
        return dealii::ExcMessage("The directory \"" + path + "\" (" + where +
                                  ") cannot be reached: symbolic links on "
                                  "its path form a loop.");
      return dealii::ExcMessage(
        "Cannot create the directory \"" + path + "\" (" + where + ")" +
        (error ? ": " + error.message() : std::string()) + ".");
    }

    /**
     * Makes the missing directories of @p path one by one, component by
     * component as written (in "a/../b" it makes a too), and returns those
     * it made, parents first; stops at the first error, which @p error
     * holds.
     */
    inline std::vector<std::filesystem::path>
    make_missing_directories(const std::string &path, std::error_code &error)
    {
      std::vector<std::filesystem::path> made;
      std::filesystem::path              partial;
      for (const auto &part : std::filesystem::path(path))
        {
          partial /= part;
          const bool exists = std::filesystem::exists(partial, error);
          if (!exists && !error &&
              std::filesystem::create_directory(partial, error))
            made.push_back(partial);
          if (error)
            break;
        }
      return made;
    }
  } // namespace internal

  /**
   * Removes the directories @p made (as create_directories() returns them)
   * that are empty, children first. Best effort, for a run that failed:
   * the error to report is the run's.
   */
  inline void
  remove_empty_directories(const std::vector<std::filesystem::path> &made)
  {
    for (auto p = made.rbegin(); p != made.rend(); ++p)
      {
        std::error_code ignored;
        std::filesystem::remove(*p, ignored); // fails on a non-empty one
      }
  }

  /**
   * Creates the directory @p path and its parents where missing, and
   * returns those it made, parents first (for remove_empty_directories()).
   * Throws ExcMessage naming @p path and the parameter @p where it comes
   * from if that fails (an empty path, a file in the way, no permission),
   * and then leaves none of them.
   */
  inline std::vector<std::filesystem::path>
  create_directories(const std::string &path, const std::string &where)
  {
    std::error_code                    error;
    std::vector<std::filesystem::path> made;
    if (!path.empty())
      made = internal::make_missing_directories(path, error);
    const bool ok =
      !path.empty() && !error && std::filesystem::is_directory(path, error);
    if (!ok)
      remove_empty_directories(made);
    AssertThrow(ok, internal::directory_error(path, where, error));
    return made;
  }

  /**
   * A result file written in one piece. stream() writes to a temporary
   * file next to @p file (partial_name()), and commit() renames it to
   * @p file once everything is written, so that a run that fails or is
   * killed while writing never leaves a truncated result under the
   * result's name. An uncommitted temporary is removed by the destructor;
   * one left by a killed run, by the next run's remove_earlier().
   */
  class ResultFile
  {
  public:
    /**
     * Opens the temporary file of @p file. Throws ExcMessage naming
     * @p file and the parameter @p where its directory comes from if it
     * cannot be opened (no directory, no permission), before anything is
     * written.
     */
    ResultFile(const std::string &file, const std::string &where);

    /// Removes the temporary file unless commit() renamed it.
    ~ResultFile();

    /// Not copyable: it owns the temporary file.
    ResultFile(const ResultFile &) = delete;
    /// Not copyable.
    ResultFile &
    operator=(const ResultFile &) = delete;

    /// The stream that writes the temporary file.
    std::ostream &
    stream();

    /**
     * Closes the temporary file and renames it to the result's name.
     * Throws ExcMessage naming the file and the parameter if a write
     * failed (a full disk shows only once the buffer is written) or the
     * rename did; the temporary is then removed and no result written.
     */
    void
    commit();

    /// The name of the temporary file of @p file: "<file>.partial".
    static std::string
    partial_name(const std::string &file);

  private:
    /// The result's name.
    std::string file;
    /// The parameter its directory comes from, named in errors.
    std::string where;
    /// The temporary file's stream.
    std::ofstream out;
    /// Whether commit() renamed the temporary file.
    bool committed;
  };

  /**
   * What @p path is if it exists and is not a regular file, with its links
   * followed: "a directory", "a named pipe", "a device", "a socket" (or "a
   * file that is not a regular file"); "" if it is a regular file, does
   * not exist, or cannot be looked at (no permission, a loop of links:
   * opening it reports that). Reading such a file fails late, never ends
   * (/dev/zero) or waits for a writer forever (a named pipe).
   */
  inline std::string
  non_regular_kind(const std::string &path)
  {
    std::error_code                  error;
    const std::filesystem::file_type type =
      std::filesystem::status(path, error).type();
    switch (type)
      {
        case std::filesystem::file_type::regular:
        case std::filesystem::file_type::not_found:
        case std::filesystem::file_type::none: // status() failed
          return "";
        case std::filesystem::file_type::directory:
          return "a directory";
        case std::filesystem::file_type::fifo:
          return "a named pipe";
        case std::filesystem::file_type::block:
        case std::filesystem::file_type::character:
          return "a device";
        case std::filesystem::file_type::socket:
          return "a socket";
        default:
          return "a file that is not a regular file";
      }
  }

  /**
   * Throws like create_directories() if the directory @p path could not be
   * made. To find out it makes the missing directories of the path one by
   * one and removes them again (only those it made, only while empty), so
   * nothing is left behind: for checks before a long run.
   */
  inline void
  check_creatable(const std::string &path, const std::string &where)
  {
    remove_empty_directories(create_directories(path, where));
  }

  /**
   * Throws ExcMessage naming @p file and the parameter @p where its
   * directory comes from if the file could not be written: something
   * other than a regular file is in the way (a directory of that name), it
   * exists in a directory that does not let remove_earlier() remove it (a
   * regular file there is removed before it is written, so its own
   * permissions do not matter), or it does not exist and cannot be
   * created; or something other than a regular file is in the way of its
   * ResultFile::partial_name(), which it is written under first. A
   * symbolic link there, also one to nowhere, counts as an earlier file
   * (remove_earlier() removes the link). Leaves an existing file as it is
   * and creates none (a missing directory is check_creatable()'s to
   * check): for checks before a long run.
   */
  void
  check_writable(const std::string &file, const std::string &where);

  /**
   * Removes the file @p file, left by an earlier run, and the temporary
   * file of a ResultFile of that name, where they exist, so that a run
   * that fails after writing some of its results leaves no earlier result
   * next to them. Throws ExcMessage naming the file and the parameter
   * @p where its directory comes from if one exists and cannot be removed.
   */
  void
  remove_earlier(const std::string &file, const std::string &where);

  /**
   * Flushes the file or directory @p path to the disk (fsync): written data
   * that must survive a crash of the machine, not only of the process,
   * before what replaces or depends on it. Returns false if that failed.
   */
  bool
  sync_to_disk(const std::string &path);

  /**
   * check_creatable() of @p directory and check_writable() of each of
   * @p files (names in it); @p where names the parameter the directory
   * comes from.
   */
  inline void
  check_writable_in(const std::string              &directory,
                    const std::vector<std::string> &files,
                    const std::string              &where)
  {
    check_creatable(directory, where);
    for (const std::string &file : files)
      check_writable(directory + "/" + file, where);
  }

  /// remove_earlier() of each of @p files (names in @p directory).
  inline void
  remove_earlier_in(const std::string              &directory,
                    const std::vector<std::string> &files,
                    const std::string              &where)
  {
    for (const std::string &file : files)
      remove_earlier(directory + "/" + file, where);
  }

  /**
   * The absolute path of @p path with the symbolic links of its existing
   * part followed (std::filesystem::weakly_canonical()), or lexically
   * normal where they cannot be followed (a directory that may not be
   * searched): for telling whether two names are one file. A final
   * separator is dropped, which the missing part of a path keeps
   * ("out/" and "out/new/.." are "out"). Never throws.
   */
  inline std::filesystem::path
  resolved_path(const std::string &path)
  {
    const auto without_final_separator = [](std::filesystem::path p) {
      return p.has_filename() || !p.has_relative_path() ? p : p.parent_path();
    };
    std::error_code             error;
    const std::filesystem::path absolute =
      std::filesystem::absolute(path, error);
    if (error)
      return without_final_separator(
        std::filesystem::path(path).lexically_normal());
    const std::filesystem::path resolved =
      std::filesystem::weakly_canonical(absolute, error);
    return without_final_separator(error ? absolute.lexically_normal() :
                                           resolved);
  }

  /**
   * Whether @p file is one of @p inputs, a run's parameter file and the
   * files it includes as resolved_path() gives them: a result file that a
   * run reads must survive its failure.
   */
  inline bool
  is_input_file(const std::string &file, const std::vector<std::string> &inputs)
  {
    return std::find(inputs.begin(),
                     inputs.end(),
                     resolved_path(file).string()) != inputs.end();
  }

  /// The extension of the file name @p file in lower case (".stl").
  inline std::string
  lowercase_extension(const std::string &file)
  {
    std::string extension = std::filesystem::path(file).extension().string();
    for (char &c : extension)
      c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return extension;
  }

  /**
   * An exclusive advisory lock (flock(2)) on the file @p path, which is
   * created if missing and left in place. The lock is held until the
   * object is destroyed or the process ends, also when it is killed, so no
   * stale lock survives a crash. While another process holds it, the
   * constructor prints what it waits for to @p out and waits.
   *
   * Where the lock file can neither be created nor opened for lack of
   * rights (a read-only place), no lock is taken: no writer without those
   * rights can be there either. On a file system without locks, a warning
   * goes to @p out and no lock is taken. Locking one path twice in one
   * process is an error (flock would wait forever).
   */
  class FileLock
  {
  public:
    /// Locks @p path (from parameter @p where, named in errors).
    FileLock(const std::string &path,
             const std::string &where,
             std::ostream      &out);

    /// Releases the lock.
    ~FileLock();

    /// Not copyable: it owns the lock.
    FileLock(const FileLock &) = delete;
    /// Not copyable.
    FileLock &
    operator=(const FileLock &) = delete;

  private:
    /// The lock file.
    std::string path;
    /// Its open file descriptor, which holds the lock (-1: no lock).
    int descriptor;
  };
} // namespace ddfem

#endif
