#ifndef ddfem_base_parsing_h
#define ddfem_base_parsing_h

#include <deal.II/base/exceptions.h>
#include <deal.II/base/point.h>
#include <deal.II/base/utilities.h>

#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace ddfem
{
  /**
   * The words of @p text separated by any amount of white space.
   */
  inline std::vector<std::string>
  split_words(const std::string &text)
  {
    std::istringstream       in(text);
    std::vector<std::string> words;
    for (std::string word; in >> word;)
      words.push_back(word);
    return words;
  }

  /**
   * The entries of the @p delimiter separated list @p text, each trimmed of
   * white space; no entries if @p text is blank. Throws ExcMessage naming
   * @p where (the parameter) if an entry is empty, as in "1,,2" or "1,2,":
   * deal.II's Utilities::split_string_list() drops a last empty entry, so
   * "E=1e5=" would pass for the pair "E=1e5".
   */
  inline std::vector<std::string>
  split_list(const std::string &text,
             const char         delimiter,
             const std::string &where)
  {
    const std::string trimmed = dealii::Utilities::trim(text);
    if (trimmed.empty())
      return {};
    const std::vector<std::string> entries =
      dealii::Utilities::split_string_list(trimmed, delimiter);
    bool empty_entry = (trimmed.back() == delimiter);
    for (const std::string &entry : entries)
      empty_entry = empty_entry || dealii::Utilities::trim(entry).empty();
    AssertThrow(!empty_entry,
                dealii::ExcMessage(where + ": \"" + trimmed +
                                   "\" has an empty entry (nothing between "
                                   "two '" +
                                   std::string(1, delimiter) +
                                   "', or after the last)."));
    return entries;
  }

  /**
   * @p text as a finite decimal number. Throws ExcMessage naming @p where
   * (the parameter) otherwise: strtod() also reads hexadecimal numbers
   * ("0x10" is 16), which no parameter in meters or pascals means.
   */
  inline double
  parse_number(const std::string &text, const std::string &where)
  {
    char        *end   = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    AssertThrow(!text.empty() && end != nullptr && *end == '\0' &&
                  std::isfinite(value) &&
                  text.find_first_of("xX") == std::string::npos,
                dealii::ExcMessage(where + ": \"" + text +
                                   "\" is not a finite decimal number."));
    return value;
  }

  /**
   * A point from exactly three numbers in @p words. Throws ExcMessage naming
   * @p where otherwise.
   */
  inline dealii::Point<3>
  parse_point(const std::vector<std::string> &words, const std::string &where)
  {
    AssertThrow(words.size() == 3,
                dealii::ExcMessage(where +
                                   ": expected three coordinates 'x, y, z'."));
    return dealii::Point<3>(parse_number(words[0], where),
                            parse_number(words[1], where),
                            parse_number(words[2], where));
  }

  /**
   * Throws ExcMessage naming @p parameter (whose value is @p text) unless
   * every one of its parsed @p entries appears once.
   */
  template <typename T>
  inline void
  check_each_once(const std::vector<T> &entries,
                  const std::string    &text,
                  const std::string    &parameter)
  {
    AssertThrow(
      std::set<T>(entries.begin(), entries.end()).size() == entries.size(),
      dealii::ExcMessage(parameter + " = " + text + ": name each entry once."));
  }

  /// check_each_once() of the entries of the comma-separated list @p text.
  inline void
  check_each_once(const std::string &text, const std::string &parameter)
  {
    check_each_once(split_list(text, ',', parameter), text, parameter);
  }

  /**
   * @p x, or +0 where @p x is -0, for the texts that identify settings (a
   * database's fingerprints): a parameter given as -0 is the setting 0,
   * which a stream writes as "-0".
   */
  inline double
  without_negative_zero(const double x)
  {
    return x == 0 ? 0. : x;
  }

  /// @p x with @p digits significant digits, for messages.
  inline std::string
  format_number(const double x, const int digits = 4)
  {
    std::ostringstream s;
    s << std::setprecision(digits) << x;
    return s.str();
  }

  /// "(x, y, z)" (as many coordinates as @p p has) with @p digits
  /// significant digits, for messages.
  template <int dim>
  std::string
  format_point(const dealii::Point<dim> &p, const int digits = 4)
  {
    std::string text = "(";
    for (unsigned int d = 0; d < dim; ++d)
      text += (d > 0 ? ", " : "") + format_number(p[d], digits);
    return text + ")";
  }
} // namespace ddfem

#endif
