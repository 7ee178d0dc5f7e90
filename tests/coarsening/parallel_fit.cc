// The worker pool of database builds (coarsening::fit_in_parallel), with
// fits that only record their index:
// - on 1, 2 and 3 threads every index is fitted and stored exactly once;
// - a fit that throws does not terminate the program: the exception
//   reaches the caller after all threads have joined, the other threads
//   start no new work (fewer than n/2 entries stored, where the failure
//   comes at 37 and the fits after it take 20 ms), and the entries of
//   the indices before it, which were all handed out earlier, are stored
//   (each once, the failing index not among them);
// - an exception from store() (a journal that cannot be written) reaches
//   the caller the same way (on one thread after exactly the entries
//   stored before it), and the threads start fewer than n/2 fits (the
//   store throws at every call from its 50th on, so the entries stored
//   alone cannot show that the pool stopped).

#include <deal.II/base/exceptions.h>

#include <ddfem/coarsening/builder.h>

#include <atomic>
#include <chrono>
#include <iostream>
#include <set>
#include <sstream>
#include <thread>

using namespace ddfem;
using namespace dealii;

namespace
{
  constexpr std::size_t n = 200;

  /// A fit that records @p i as its key, and throws at index @p fail.
  coarsening::Entry
  fit(const std::size_t i, const std::size_t fail)
  {
    AssertThrow(i != fail, ExcMessage("fit " + std::to_string(i) + " failed"));
    // Long enough for the threads to interleave; the fits after a failing
    // one take longer, so that the stop is seen well before n/2 even on a
    // loaded machine.
    std::this_thread::sleep_for(std::chrono::milliseconds(i > fail ? 20 : 1));
    coarsening::Entry entry;
    entry.key = i;
    return entry;
  }

  /// Runs the pool; fit() throws at @p fail_fit, store() at its
  /// @p fail_store-th call. Prints what reached the caller and what was
  /// stored.
  void
  run(const unsigned int threads,
      const std::size_t  fail_fit,
      const std::size_t  fail_store)
  {
    std::vector<std::size_t> stored;
    std::atomic<std::size_t> fits_started(0);
    std::ostringstream       progress;
    std::string              error = "none";
    try
      {
        coarsening::fit_in_parallel(
          n,
          threads,
          [&](const std::size_t i) {
            ++fits_started;
            return fit(i, fail_fit);
          },
          [&](const coarsening::Entry &entry) {
            AssertThrow(stored.size() != fail_store,
                        ExcMessage("journal full"));
            stored.push_back(entry.key);
          },
          progress,
          false);
      }
    catch (const ExceptionBase &e)
      {
        const std::string what = e.what();
        error = what.find("fit " + std::to_string(fail_fit) + " failed") !=
                    std::string::npos ?
                  "the failing fit's" :
                what.find("journal full") != std::string::npos ? "the store's" :
                                                                 "another";
      }
    const std::set<std::size_t> distinct(stored.begin(), stored.end());
    // The indices below k that were stored.
    const auto n_below = [&](const std::size_t k) {
      return std::distance(distinct.begin(), distinct.lower_bound(k));
    };
    std::cout << threads << " thread(s): exception " << error
              << "; each entry stored once: "
              << (distinct.size() == stored.size() ? "true" : "false");
    if (fail_fit >= n && fail_store >= n)
      std::cout << "; all " << n
                << " stored: " << (stored.size() == n ? "true" : "false");
    else
      std::cout << "; stopped (fewer than " << n / 2 << " stored, and fits "
                << "started): "
                << (stored.size() < n / 2 && fits_started < n / 2 ? "true" :
                                                                    "false");
    if (fail_fit < n)
      std::cout << "; failing index stored: "
                << (distinct.count(fail_fit) ? "true" : "false")
                << "; every index before it stored: "
                << (n_below(fail_fit) == std::ptrdiff_t(fail_fit) ? "true" :
                                                                    "false");
    if (fail_store < n && threads == 1)
      std::cout << "; stored exactly the first " << fail_store << ": "
                << (n_below(fail_store) == std::ptrdiff_t(fail_store) &&
                        stored.size() == fail_store ?
                      "true" :
                      "false");
    std::cout << std::endl;
  }
} // namespace

int
main()
{
  std::cout << "No failure" << std::endl;
  for (const unsigned int threads : {1u, 2u, 3u})
    run(threads, n, n);
  std::cout << "fit(37) throws" << std::endl;
  for (const unsigned int threads : {1u, 2u, 3u})
    run(threads, 37, n);
  std::cout << "The 50th store throws" << std::endl;
  for (const unsigned int threads : {1u, 2u, 3u})
    run(threads, n, 50);
}
