// FileLock, which lets two ddfem processes that use the same metamaterial
// database take turns: while another process holds the lock, a second one
// says that it waits and waits until the holder releases it or is killed.
// Locking a path twice in one process, and a lock file that cannot be
// created, are errors naming the parameter.

#include <ddfem/base/exceptions.h>
#include <ddfem/base/files.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <functional>
#include <iostream>
#include <sstream>
#include <thread>

#include "../tests.h"

namespace
{
  /// A string stream that tells when a line was flushed into it.
  class LineSignal : public std::stringbuf
  {
  public:
    std::atomic<bool> flushed{false};

  protected:
    int
    sync() override
    {
      flushed = true;
      return std::stringbuf::sync();
    }
  };

  /// A child process that holds the lock on @p path until it reads a byte
  /// from the returned pipe (or is killed); returns once it holds it.
  std::pair<pid_t, int>
  holder(const std::string &path)
  {
    int ready[2], go[2];
    AssertThrow(pipe(ready) == 0 && pipe(go) == 0, dealii::ExcInternalError());
    const pid_t child = fork();
    AssertThrow(child >= 0, dealii::ExcInternalError());
    if (child == 0)
      {
        alarm(120); // never outlive a test that died
        char byte = 1;
        {
          std::ostringstream    quiet;
          const ddfem::FileLock lock(path, "Database/File", quiet);
          if (write(ready[1], &byte, 1) != 1 || read(go[0], &byte, 1) != 1)
            _exit(1);
        }
        _exit(0);
      }
    char byte = 0;
    AssertThrow(read(ready[0], &byte, 1) == 1, dealii::ExcInternalError());
    close(ready[0]);
    close(ready[1]);
    close(go[0]);
    return {child, go[1]};
  }

  /// Takes the lock on @p path in a thread while another process holds
  /// it: reports whether the thread got it before it said it waits, and
  /// after @p release whether it got it then.
  void
  second_lock(const std::string &path, const std::function<void()> &release)
  {
    std::atomic<bool> acquired(false);
    LineSignal        buffer;
    std::ostream      message(&buffer);
    std::thread       waiter([&] {
      const ddfem::FileLock lock(path, "Database/File", message);
      acquired = true;
    });
    for (unsigned int i = 0; i < 6000 && !buffer.flushed; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    std::cout << "  said that it waits: " << buffer.flushed.load()
              << ", acquired while the other holds it: " << acquired
              << std::endl;
    release();
    waiter.join();
    std::cout << "  acquired after the release: " << acquired << std::endl
              << "  " << buffer.str();
  }
} // namespace

int
main()
{
  std::cout << std::boolalpha;
  const std::string path = "db.h5.lock";

  std::cout << "A lock held by another process that releases it:" << std::endl;
  {
    const auto [child, go] = holder(path);
    second_lock(path, [child = child, go = go] {
      const char byte = 1;
      AssertThrow(write(go, &byte, 1) == 1, dealii::ExcInternalError());
      waitpid(child, nullptr, 0);
      close(go);
    });
  }

  std::cout << "A lock held by another process that is killed:" << std::endl;
  {
    const auto [child, go] = holder(path);
    second_lock(path, [child = child, go = go] {
      kill(child, SIGKILL);
      waitpid(child, nullptr, 0);
      close(go);
    });
  }

  const auto error = [](const std::function<void()> &f) {
    try
      {
        f();
        std::cout << "  no error" << std::endl;
      }
    catch (const dealii::ExceptionBase &e)
      {
        std::cout << "  " << ddfem::message_of(e) << std::endl;
      }
  };
  std::cout << "The same path locked twice in one process:" << std::endl;
  error([&path] {
    const ddfem::FileLock first(path, "Database/File", std::cout);
    const ddfem::FileLock second(path, "Database/File", std::cout);
  });
  std::cout << "Locked again after the first lock is gone:" << std::endl;
  error(
    [&path] { const ddfem::FileLock again(path, "Database/File", std::cout); });
  std::cout << "A lock file in a missing directory:" << std::endl;
  error([] {
    const ddfem::FileLock lock("missing/db.h5.lock",
                               "Database/File",
                               std::cout);
  });
}
