#ifndef ddfem_base_statistics_h
#define ddfem_base_statistics_h

#include <deal.II/base/exceptions.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace ddfem
{
  /**
   * The @p q quantile (0 <= q <= 1) of the ascending values @p sorted:
   * sorted[min(n - 1, floor(q n))], so that at most a fraction 1 - q of the
   * values lies above it. The median of an even count is the upper middle
   * value; q = 1 gives the largest. @p sorted must not be empty.
   */
  inline double
  quantile(const std::vector<double> &sorted, const double q)
  {
    Assert(!sorted.empty(), dealii::ExcEmptyObject());
    const std::size_t n = sorted.size();
    // floor(q n), also where q n rounds below an integer (0.29 * 100 is
    // 28.999999999999996): the largest i with i / n <= q.
    std::size_t i = std::min<std::size_t>(n - 1, q * n);
    while (i + 1 < n && double(i + 1) / n <= q)
      ++i;
    return sorted[i];
  }

  /// Whether every value of @p values (a vector of doubles) is finite.
  template <typename Container>
  inline bool
  all_finite(const Container &values)
  {
    return std::all_of(values.begin(), values.end(), [](const double v) {
      return std::isfinite(v);
    });
  }

  /**
   * The smaller of @p a and @p b, and NaN if either is NaN (std::min
   * returns its first argument when compared with a NaN), so that a minimum
   * taken over values with a NaN among them fails a check such as
   * `!(minimum > 0)`.
   */
  inline double
  min_or_nan(const double a, const double b)
  {
    return std::isnan(a) || std::isnan(b) ? std::nan("") : std::min(a, b);
  }

  /**
   * The smallest of a sequence of values and where it was seen.
   *
   * Of values equal up to round-off (a relative 1e-9), the first seen is
   * kept, so that the place reported for symmetric cells or vertices does
   * not depend on the round-off of whatever computed the values. A NaN
   * compares below every number: the first NaN seen is kept, so that a
   * check such as `!(value() > 0)` fails on it.
   */
  template <typename Place>
  class FirstSmallest
  {
  public:
    /// Offers @p value, seen at @p place.
    void
    add(const double value, const Place &place)
    {
      if (std::isnan(smallest))
        return;
      if (std::isnan(value) ||
          value <
            smallest - (std::isfinite(value) ? 1e-9 * std::abs(value) : 0))
        {
          smallest = value;
          where    = place;
        }
    }

    /// The smallest value offered; infinity if none was.
    double
    value() const
    {
      return smallest;
    }

    /// Where value() was seen; a default Place if nothing was offered.
    const Place &
    place() const
    {
      return where;
    }

  private:
    double smallest = std::numeric_limits<double>::infinity();
    Place  where{};
  };
} // namespace ddfem

#endif
