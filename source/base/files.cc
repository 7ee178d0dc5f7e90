#include <ddfem/base/files.h>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <mutex>
#include <set>

namespace ddfem
{
  namespace
  {
    /// The paths this process holds a FileLock on (flock would make a
    /// second lock of the same file in one process wait forever).
    std::set<std::string> held_paths;
    std::mutex            held_paths_mutex;

    /// Whether @p error says the file system does not support flock.
    bool
    unsupported(const int error)
    {
      return error == ENOLCK || error == EOPNOTSUPP || error == ENOSYS ||
             error == EINVAL;
    }
  } // namespace



  bool
  sync_to_disk(const std::string &path)
  {
    const int descriptor = ::open(path.c_str(), O_RDONLY);
    if (descriptor < 0)
      return false;
    const bool synced = (::fsync(descriptor) == 0);
    ::close(descriptor);
    return synced;
  }



  ResultFile::ResultFile(const std::string &file, const std::string &where)
    : file(file)
    , where(where)
    , out(partial_name(file))
    , committed(false)
  {
    AssertThrow(out,
                dealii::ExcMessage("Cannot write \"" + file + "\" (" + where +
                                   "): " + std::strerror(errno) + "."));
  }



  ResultFile::~ResultFile()
  {
    if (!committed)
      {
        out.close();
        std::error_code ignored;
        std::filesystem::remove(partial_name(file), ignored);
      }
  }



  std::ostream &
  ResultFile::stream()
  {
    return out;
  }



  void
  ResultFile::commit()
  {
    out.close();
    std::error_code error;
    if (out)
      std::filesystem::rename(partial_name(file), file, error);
    AssertThrow(out && !error,
                dealii::ExcMessage(
                  "Cannot write \"" + file + "\" (" + where + ")" +
                  (error ? ": " + error.message() : std::string()) + "."));
    committed = true;
  }



  std::string
  ResultFile::partial_name(const std::string &file)
  {
    return file + ".partial";
  }



  void
  check_writable(const std::string &file, const std::string &where)
  {
    std::error_code             error;
    const std::filesystem::path path(file);
    if (!std::filesystem::is_directory(path.parent_path().empty() ?
                                         std::filesystem::path(".") :
                                         path.parent_path(),
                                       error))
      return;
    // A symbolic link is removed by remove_earlier(), not written through:
    // what it names is not in the way, and the check must not make it.
    const auto in_the_way = [&error](const std::string &name) {
      return std::filesystem::is_symlink(
               std::filesystem::symlink_status(name, error)) ?
               std::string() :
               non_regular_kind(name);
    };
    const std::string partial      = ResultFile::partial_name(file);
    const std::string partial_kind = in_the_way(partial);
    AssertThrow(partial_kind.empty(),
                dealii::ExcMessage("Cannot write \"" + file + "\" (" + where +
                                   "): " + partial_kind +
                                   " is in the way of \"" + partial +
                                   "\", which it is written under first."));
    const bool existed =
      std::filesystem::exists(std::filesystem::symlink_status(path, error));
    const std::string directory =
      path.parent_path().empty() ? "." : path.parent_path().string();
    AssertThrow(!existed || access(directory.c_str(), W_OK) == 0,
                dealii::ExcMessage("Cannot replace \"" + file + "\" (" + where +
                                   "): its directory is not "
                                   "writable, so the file of an "
                                   "earlier run cannot be removed."));
    const std::string kind = in_the_way(file);
    AssertThrow(kind.empty(),
                dealii::ExcMessage("Cannot write \"" + file + "\" (" + where +
                                   "): " + kind +
                                   " of that name is in the way."));
    if (existed)
      return;
    const bool ok = static_cast<bool>(std::ofstream(file));
    std::filesystem::remove(path, error);
    AssertThrow(ok,
                dealii::ExcMessage("Cannot write \"" + file + "\" (" + where +
                                   ")."));
  }



  void
  remove_earlier(const std::string &file, const std::string &where)
  {
    for (const std::string &name : {file, ResultFile::partial_name(file)})
      {
        std::error_code error;
        std::filesystem::remove(name, error);
        AssertThrow(!error,
                    dealii::ExcMessage("Cannot remove \"" + name +
                                       "\", a result of an earlier run (" +
                                       where + "): " + error.message() + "."));
      }
  }



  FileLock::FileLock(const std::string &path,
                     const std::string &where,
                     std::ostream      &out)
    : path(path)
    , descriptor(-1)
  {
    {
      std::lock_guard<std::mutex> guard(held_paths_mutex);
      AssertThrow(held_paths.insert(path).second,
                  dealii::ExcMessage("\"" + path + "\" (" + where +
                                     ") is locked twice by this process."));
    }
    const auto fail = [&](const std::string &what, const int error) {
      if (descriptor >= 0)
        ::close(descriptor);
      std::lock_guard<std::mutex> guard(held_paths_mutex);
      held_paths.erase(path);
      AssertThrow(false,
                  dealii::ExcMessage(what + " \"" + path + "\" (" + where +
                                     "): " + std::strerror(error) + "."));
    };

    descriptor = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (descriptor < 0 && (errno == EACCES || errno == EROFS))
      {
        // A read-only place: another user's lock file, or a database that
        // this process can read but not change (nor can any writer
        // without the rights to make the lock file). flock works on a
        // read-only descriptor; without one, there is nothing to guard.
        descriptor = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (descriptor < 0 && (errno == ENOENT || errno == EACCES))
          return;
      }
    if (descriptor < 0)
      fail("Cannot create the lock file", errno);

    if (::flock(descriptor, LOCK_EX | LOCK_NB) == 0)
      return;
    int error = errno;
    if (unsupported(error))
      {
        out << "Warning: the file system of \"" << path
            << "\" does not support locks (" << std::strerror(error)
            << "); runs that use the file at the same time may lose each "
               "other's entries."
            << std::endl;
        ::close(descriptor);
        descriptor = -1;
        return;
      }
    if (error == EWOULDBLOCK)
      {
        out << "Waiting for another ddfem process that is using \"" << path
            << "\" (" << where << ") to finish" << std::endl;
        int result;
        do
          result = ::flock(descriptor, LOCK_EX);
        while (result != 0 && errno == EINTR);
        if (result == 0)
          return;
        error = errno;
      }
    fail("Cannot lock", error);
  }



  FileLock::~FileLock()
  {
    if (descriptor >= 0)
      ::close(descriptor); // releases the lock
    std::lock_guard<std::mutex> guard(held_paths_mutex);
    held_paths.erase(path);
  }
} // namespace ddfem
