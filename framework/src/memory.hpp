// What a run may allocate: the machine's physical memory, against which the mesh generators and
// the point driver check their estimates before they allocate (refused up front with the
// estimate, rather than by std::bad_alloc or the kernel after minutes of work).
#pragma once

#include <string>

namespace stratum {

/// Physical memory of the machine in bytes; 0 when it cannot be told.
[[nodiscard]] double physical_memory();

/// "" when `need` bytes fit in the machine's memory (or it cannot be told), else the sentence
/// "<what> would need about X GB of memory (<basis>); this machine has Y GB".
[[nodiscard]] std::string memory_shortfall(double need, const std::string& what, const std::string& basis);

} // namespace stratum
