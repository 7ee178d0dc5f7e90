#ifndef ddfem_base_exceptions_h
#define ddfem_base_exceptions_h

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <sstream>
#include <string>

namespace ddfem
{
  /**
   * The user-facing part of a deal.II exception: its "additional
   * information" without file, line, condition or stack trace, trimmed.
   */
  inline std::string
  message_of(const dealii::ExceptionBase &exception)
  {
    std::ostringstream message;
    exception.print_info(message);
    return dealii::Utilities::trim(message.str());
  }
} // namespace ddfem

#endif
