// quantile(), behind every median and percentile ddfem reports (the fits'
// held-out errors, the principal strains of summary.json): the value with
// index floor(q n) of n sorted values, so that at most a fraction 1 - q
// lies above it. Known answers for 1, 2, 100 and 1000 values, among them
// q n that floating point rounds below an integer (0.29 * 100 and
// 0.57 * 100 are 28.999999999999996 and 56.99999999999999).
//
// FirstSmallest, which the fine solver and DG use to report the most
// compressed corner: of values equal up to round-off the first is kept, a
// smaller value beyond round-off replaces it (also -inf), and a NaN is
// kept once seen.

#include <ddfem/base/statistics.h>

#include <iomanip>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

int
main()
{
  const auto print = [](const std::vector<double> &sorted, const double q) {
    std::cout << "  q = " << q << ": " << ddfem::quantile(sorted, q)
              << std::endl;
  };
  std::cout << "one value (7):" << std::endl;
  for (const double q : {0., 0.5, 1.})
    print({7.}, q);
  std::cout << "two values (1, 2): the median is the upper one" << std::endl;
  for (const double q : {0., 0.49, 0.5, 1.})
    print({1., 2.}, q);
  std::vector<double> hundred, thousand;
  for (int i = 1; i <= 100; ++i)
    hundred.push_back(i);
  for (int i = 1; i <= 1000; ++i)
    thousand.push_back(i);
  std::cout << "1, 2, ..., 100: the value floor(100 q) + 1, at most 100"
            << std::endl;
  for (const double q : {0., 0.1, 0.29, 0.5, 0.57, 0.9, 0.99, 1.})
    print(hundred, q);
  std::cout << "1, 2, ..., 1000: the value floor(1000 q) + 1, at most 1000"
            << std::endl;
  for (const double q : {0.001, 0.1, 0.5, 0.9, 0.99, 0.999, 1.})
    print(thousand, q);

  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const auto   smallest_of =
    [](const std::vector<std::pair<double, std::string>> &values) {
      ddfem::FirstSmallest<std::string> smallest;
      for (const auto &[value, place] : values)
        smallest.add(value, place);
      std::cout << "  " << std::setprecision(12) << smallest.value() << " at '"
                << smallest.place() << "'" << std::endl;
    };
  std::cout << "FirstSmallest:" << std::endl;
  smallest_of({});
  smallest_of({{0.5, "a"}, {0.5 * (1 - 1e-12), "b"}, {0.5 * (1 + 1e-12), "c"}});
  smallest_of({{0.5, "a"}, {0.5 * (1 - 1e-8), "b"}, {0.7, "c"}});
  smallest_of({{-2, "a"}, {-2 * (1 + 1e-12), "b"}, {-2 * (1 + 1e-8), "c"}});
  smallest_of({{0.5, "a"}, {nan, "b"}, {-1, "c"}, {nan, "d"}});
  smallest_of({{nan, "a"}, {0.5, "b"}});
  smallest_of({{0.5, "a"}, {-inf, "b"}, {-1, "c"}});
}
