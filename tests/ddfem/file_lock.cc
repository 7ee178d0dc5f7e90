// FileLock, which lets two ddfem processes that use the same metamaterial
// database take turns: a second lock on the file waits, saying so, until
// the first is released; a process killed while holding the lock releases
// it; a lock file that cannot be created is an error naming the parameter.

#include <ddfem/base/exceptions.h>
#include <ddfem/base/files.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <functional>
#include <iostream>
#include <memory>
#include <sstream>
#include <thread>

#include "../tests.h"

namespace
{
  /// Takes the lock on @p path in a thread; reports whether it got it
  /// within 300 ms, and after @p release whether it got it then.
  void
  second_lock(const std::string &path, const std::function<void()> &release)
  {
    std::atomic<bool>  acquired(false);
    std::ostringstream message;
    std::thread        waiter([&] {
      const ddfem::FileLock lock(path, "Database/File", message);
      acquired = true;
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    std::cout << "  second lock acquired while the first is held: " << acquired
              << std::endl;
    release();
    waiter.join();
    std::cout << "  second lock acquired after the release: " << acquired
              << std::endl
              << "  " << message.str();
  }
} // namespace

int
main()
{
  std::cout << std::boolalpha;

  std::cout << "Two locks in one process:" << std::endl;
  auto first =
    std::make_unique<ddfem::FileLock>("db.h5.lock", "Database/File", std::cout);
  second_lock("db.h5.lock", [&first] { first.reset(); });

  std::cout << "A lock held by a process that is killed:" << std::endl;
  int channel[2];
  AssertThrow(pipe(channel) == 0, dealii::ExcInternalError());
  const pid_t child = fork();
  if (child == 0)
    {
      std::ostringstream    quiet;
      const ddfem::FileLock lock("db.h5.lock", "Database/File", quiet);
      const char            ready = 1;
      if (write(channel[1], &ready, 1) != 1)
        _exit(1);
      pause();
      _exit(0);
    }
  char ready = 0;
  AssertThrow(read(channel[0], &ready, 1) == 1, dealii::ExcInternalError());
  second_lock("db.h5.lock", [child] {
    kill(child, SIGKILL);
    waitpid(child, nullptr, 0);
  });

  std::cout << "A lock file in a missing directory:" << std::endl;
  try
    {
      const ddfem::FileLock lock("missing/db.h5.lock",
                                 "Database/File",
                                 std::cout);
    }
  catch (const dealii::ExceptionBase &e)
    {
      std::cout << "  " << ddfem::message_of(e) << std::endl;
    }
}
