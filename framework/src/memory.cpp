#include "memory.hpp"

#include <cstdio>

#include <unistd.h>

namespace stratum {

double physical_memory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 0.0;
}

std::string memory_shortfall(double need, const std::string& what, const std::string& basis) {
  const double have = physical_memory();
  if (!(have > 0) || need <= have) return {};
  char buf[120];
  std::snprintf(buf, sizeof buf, " would need about %.1f GB of memory (", need / 1e9);
  std::string s = what + buf + basis;
  std::snprintf(buf, sizeof buf, "); this machine has %.1f GB", have / 1e9);
  return s + buf;
}

} // namespace stratum
