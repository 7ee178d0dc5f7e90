#include <ddfem/base/files.h>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace ddfem
{
  FileLock::FileLock(const std::string &path,
                     const std::string &where,
                     std::ostream      &out)
    : descriptor(::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644))
  {
    AssertThrow(descriptor >= 0,
                dealii::ExcMessage("Cannot create the lock file \"" + path +
                                   "\" (" + where +
                                   "): " + std::strerror(errno) + "."));
    if (::flock(descriptor, LOCK_EX | LOCK_NB) == 0)
      return;
    if (errno == EWOULDBLOCK)
      out << "Waiting for another ddfem process that is using \"" << path
          << "\" (" << where << ") to finish" << std::endl;
    int result = -1;
    if (errno == EWOULDBLOCK)
      while ((result = ::flock(descriptor, LOCK_EX)) != 0 && errno == EINTR)
        ;
    if (result != 0)
      {
        const std::string error = std::strerror(errno);
        ::close(descriptor);
        AssertThrow(false,
                    dealii::ExcMessage("Cannot lock \"" + path + "\" (" +
                                       where + "): " + error + "."));
      }
  }



  FileLock::~FileLock()
  {
    ::close(descriptor); // releases the lock
  }
} // namespace ddfem
