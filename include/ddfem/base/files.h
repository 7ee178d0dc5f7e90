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

  /**
   * Throws like create_directories() if the directory @p path could not be
   * made. To find out it makes the missing part of the path and removes it
   * again, so nothing is left behind: for checks before a long run.
   */
  inline void
  check_creatable(const std::string &path, const std::string &where)
  {
    std::filesystem::path missing;
    if (!path.empty())
      for (std::filesystem::path p = std::filesystem::absolute(path);
           !p.empty() && !std::filesystem::exists(p) && p != p.parent_path();
           p = p.parent_path())
        missing = p;
    create_directories(path, where);
    if (!missing.empty())
      std::filesystem::remove_all(missing);
  }
} // namespace ddfem

#endif
