#ifndef ddfem_base_files_h
#define ddfem_base_files_h

#include <deal.II/base/exceptions.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace ddfem
{
  /**
   * Creates the directory @p path and its parents where missing. Throws
   * ExcMessage naming @p path and the parameter @p where it comes from if
   * that fails (an empty path, a file in the way, no permission).
   */
  inline void
  create_directories(const std::string &path, const std::string &where)
  {
    std::error_code error;
    if (!path.empty())
      std::filesystem::create_directories(path, error);
    AssertThrow(!path.empty() && !error && std::filesystem::is_directory(path),
                dealii::ExcMessage(
                  "Cannot create the directory \"" + path + "\" (" + where +
                  ")" + (error ? ": " + error.message() : std::string()) +
                  "."));
  }
} // namespace ddfem

#endif
