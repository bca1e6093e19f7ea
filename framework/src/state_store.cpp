#include "stratum/state_store.hpp"

#include <algorithm>

namespace stratum {

StateStore::StateStore(std::size_t points, int history_size)
    : points_(points), history_(history_size), committed_(points * static_cast<std::size_t>(stride()), 0.0),
      trial_(committed_) {}

void StateStore::commit() {
  // Every evaluation rewrites every slot of the store, so committing is a swap: the old
  // committed array becomes scratch that the next evaluation overwrites.
  committed_.swap(trial_);
}

void StateStore::revert() { std::copy(committed_.begin(), committed_.end(), trial_.begin()); }

} // namespace stratum
