#ifndef ddfem_base_memory_h
#define ddfem_base_memory_h

#include <unistd.h>

namespace ddfem
{
  /**
   * The physical memory of the machine in bytes (not a container's
   * limit), or 0 if the system does not say. Runs refuse sizes that could
   * not fit into it with a message naming the parameter, rather than end
   * in the system's out-of-memory killer.
   */
  inline double
  physical_memory()
  {
    const long pages = sysconf(_SC_PHYS_PAGES);
    const long size  = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? static_cast<double>(pages) * size : 0.;
  }
} // namespace ddfem

#endif
