#ifndef ddfem_tests_threads_h
#define ddfem_tests_threads_h

// For the tests that compare results with one thread and with two.

#include <deal.II/base/multithread_info.h>
#include <deal.II/base/work_stream.h>

#include <chrono>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

namespace ddfem::testing
{
  using namespace dealii;

  /**
   * The number of threads that run the items of a WorkStream, the loop of
   * the assemblies, with the thread limit @p threads. Each item takes a
   * millisecond, so that with two threads both take some. A test that
   * compares one thread with two prints it: with one running, its
   * comparisons could not fail.
   */
  inline unsigned int
  threads_running(const unsigned int threads)
  {
    MultithreadInfo::set_thread_limit(threads);
    std::set<std::thread::id> ids;
    std::mutex                mutex;
    struct Empty
    {};
    std::vector<unsigned int> items(64);
    WorkStream::run(
      items.begin(),
      items.end(),
      [&](const std::vector<unsigned int>::iterator &, Empty &, Empty &) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        const std::lock_guard<std::mutex> lock(mutex);
        ids.insert(std::this_thread::get_id());
      },
      [](const Empty &) {},
      Empty(),
      Empty());
    return ids.size();
  }
} // namespace ddfem::testing

#endif
