// FileLock, which lets two ddfem processes that use the same metamaterial
// database take turns: while another process holds the lock, a second one
// says that it waits and waits until the holder releases it or is killed.
// The database runs (Run type = database, and a ddfem simulation fitting
// lazily) wait for the lock before they read the file: they find the entry
// the holder saved just before it released the lock. Locking a path twice
// in one process, and a lock file that cannot be created, are errors naming
// the parameter.

#include <ddfem/base/exceptions.h>
#include <ddfem/base/files.h>
#include <ddfem/coarsening/database.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <thread>

#include "../tests.h"

namespace
{
  /// A string stream that tells when the lock's waiting message was
  /// flushed into it.
  class LineSignal : public std::stringbuf
  {
  public:
    std::atomic<bool> flushed{false};

  protected:
    int
    sync() override
    {
      if (str().find("Waiting for another ddfem process") != std::string::npos)
        flushed = true;
      return std::stringbuf::sync();
    }
  };

  /// A child process that holds the lock on @p path until it reads a byte
  /// from the returned pipe (or is killed); returns once it holds it. If
  /// @p publish is given, the child copies that file to db.h5 before it
  /// releases the lock, as a build that saves its entries does.
  std::pair<pid_t, int>
  holder(const std::string &path, const std::string &publish = "")
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
          if (!publish.empty())
            std::filesystem::copy_file(
              publish,
              "db.h5",
              std::filesystem::copy_options::overwrite_existing);
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

  /// Runs @p job (which writes to the given stream) in a thread while
  /// another process holds the lock: reports whether it said that it waits
  /// and whether it finished while the other held the lock (half a second
  /// after it said so), and after @p release whether it finished within a
  /// minute (if not, the test ends with exit code 1).
  /// Returns what the job wrote.
  std::string
  while_locked(const std::function<void(std::ostream &)> &job,
               const std::function<void()>               &release)
  {
    std::atomic<bool> finished(false);
    LineSignal        buffer;
    std::ostream      message(&buffer);
    std::thread       waiter([&] {
      job(message);
      finished = true;
    });
    for (unsigned int i = 0; i < 6000 && !buffer.flushed; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    std::cout << "  said that it waits: " << buffer.flushed.load()
              << ", finished while the other holds the lock: " << finished
              << std::endl;
    release();
    for (unsigned int i = 0; i < 6000 && !finished; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    std::cout << "  finished within a minute of the release: " << finished
              << std::endl;
    if (!finished)
      std::_Exit(1); // the waiter cannot be joined
    waiter.join();
    return buffer.str();
  }

  /// Releases the lock of holder() @p child by writing to its pipe @p go.
  std::function<void()>
  release(const pid_t child, const int go)
  {
    return [child, go] {
      const char byte = 1;
      AssertThrow(write(go, &byte, 1) == 1, dealii::ExcInternalError());
      waitpid(child, nullptr, 0);
      close(go);
    };
  }

  /// Takes the lock on @p path in a thread (while_locked()) and prints the
  /// message it wrote.
  void
  second_lock(const std::string &path, const std::function<void()> &release)
  {
    const std::string message = while_locked(
      [&path](std::ostream &out) {
        const ddfem::FileLock lock(path, "Database/File", out);
      },
      release);
    std::cout << "  " << message;
  }

  /// A ddfem run of a 2x2x2-voxel cantilever with @p settings whose
  /// metamaterials go into db.h5 (one homogeneous block, cheap sampling).
  /// Prints its exit status and the entries of db.h5 afterwards.
  std::function<void(std::ostream &)>
  ddfem_run(const std::string &name, const std::string &settings)
  {
    return [name, settings](std::ostream &out) {
      std::ofstream(name + ".prm")
        << ddfem::testing::cantilever("2, 2, 2", "0; 0; -1000") << settings
        << ddfem::testing::cheap_lazy_database("db.h5")
        << ddfem::testing::quiet_output(name);
      const int status = ddfem::app::run({name + ".prm"}, out, out);
      out << "exit status " << status << ", entries in db.h5: "
          << ddfem::coarsening::Database::load("db.h5").entries().size()
          << std::endl;
    };
  }

  /// The line of @p text that says how many entries the database holds
  /// and how many are to be fitted.
  std::string
  entries_line(const std::string &text)
  {
    const std::size_t start = text.find("Metamaterial database");
    return start == std::string::npos ?
             "(no such line)" :
             text.substr(start, text.find('\n', start) - start);
  }

  /// The last line of @p text.
  std::string
  last_line(const std::string &text)
  {
    const std::size_t end   = text.find_last_not_of('\n');
    const std::size_t start = text.rfind('\n', end);
    return text.substr(start == std::string::npos ? 0 : start + 1,
                       end - (start == std::string::npos ? 0 : start + 1) + 1);
  }
} // namespace

int
main(int argc, char **argv)
{
  std::cout << std::boolalpha;
  const std::string path = "db.h5.lock";

  std::cout << "A lock held by another process that releases it:" << std::endl;
  {
    const auto [child, go] = holder(path);
    second_lock(path, release(child, go));
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

  // The runs that read and write the database hold its lock from before
  // they read it until their new entries are saved. The holders below save
  // the cantilever's entry into db.h5 just before they release the lock: a
  // run that read the file before it held the lock would find no entry
  // and fit it again.
  ddfem::testing::remove_database("db.h5");
  {
    std::ostringstream quiet;
    ddfem_run("prepare", "set Run type = database\n")(quiet);
    std::filesystem::rename("db.h5", "prepared.h5");
  }
  std::cout << "Run type = database while another process holds the lock:"
            << std::endl;
  {
    const auto [child, go] = holder(path, "prepared.h5");
    const std::string message =
      while_locked(ddfem_run("database_run", "set Run type = database\n"),
                   release(child, go));
    std::cout << "  " << entries_line(message) << "\n  " << last_line(message)
              << std::endl;
  }
  std::cout << "Method = ddfem (lazy fits) while another process holds the "
               "lock:"
            << std::endl;
  ddfem::testing::remove_database("db.h5");
  {
    const auto [child, go] = holder(path, "prepared.h5");
    // A simulation needs MPI (its linear algebra); no process is forked
    // after this.
    const dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
    const std::string                              message =
      while_locked(ddfem_run("ddfem_run",
                             "set Method = ddfem\nset Coarsening levels = 1\n"),
                   release(child, go));
    std::cout << "  " << entries_line(message) << "\n  " << last_line(message)
              << std::endl;
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
