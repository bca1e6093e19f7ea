#include "stratum/state_store.hpp"

#include <algorithm>
#include <stdexcept>

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

void StateStore::hold(std::size_t first, std::size_t last) {
  const auto s = static_cast<std::size_t>(stride());
  std::copy(committed_.begin() + static_cast<std::ptrdiff_t>(first * s),
            committed_.begin() + static_cast<std::ptrdiff_t>(last * s),
            trial_.begin() + static_cast<std::ptrdiff_t>(first * s));
}

void StateStore::restore(const std::vector<double>& committed) {
  if (committed.size() != committed_.size())
    throw std::invalid_argument("StateStore::restore: size mismatch");
  committed_ = committed;
  trial_ = committed;
}

} // namespace stratum
