// Framework-owned history of integration points.
//
// Each integration point owns a slot of `stride()` doubles laid out as
//   [ stress (6) | strain (6) | material history (history_size) ].
// Two flat arrays hold the committed and the trial states. commit() swaps them:
// the trial becomes committed and the old committed array is scratch until the
// next evaluation rewrites it (every evaluation writes every slot of a store;
// between commit() and that evaluation, read committed(), not trial()).
// revert() discards the trial by copying the committed array over it.
#pragma once

#include "stratum/voigt.hpp"

#include <cstddef>
#include <span>
#include <vector>

namespace stratum {

/// A view on one integration point's slot.
template <class T> struct PointSlot {
  T* data = nullptr;
  int history_size = 0;

  [[nodiscard]] auto stress() const {
    return Eigen::Map<std::conditional_t<std::is_const_v<T>, const Vec6, Vec6>>(data);
  }
  [[nodiscard]] auto strain() const {
    return Eigen::Map<std::conditional_t<std::is_const_v<T>, const Vec6, Vec6>>(data + 6);
  }
  [[nodiscard]] std::span<T> history() const { return {data + 12, static_cast<std::size_t>(history_size)}; }
};

class StateStore {
public:
  static constexpr int fixed = 12; ///< stress + strain

  StateStore() = default;
  /// `points` integration points with `history_size` history values each; all zero.
  StateStore(std::size_t points, int history_size);

  [[nodiscard]] std::size_t points() const { return points_; }
  [[nodiscard]] int history_size() const { return history_; }
  [[nodiscard]] int stride() const { return fixed + history_; }

  [[nodiscard]] PointSlot<const double> committed(std::size_t p) const {
    return {committed_.data() + p * stride(), history_};
  }
  [[nodiscard]] PointSlot<double> trial(std::size_t p) { return {trial_.data() + p * stride(), history_}; }
  [[nodiscard]] PointSlot<const double> trial(std::size_t p) const {
    return {trial_.data() + p * stride(), history_};
  }
  /// Writable committed slot: only for initialisation (initial stress, history defaults).
  [[nodiscard]] PointSlot<double> committed_for_init(std::size_t p) {
    return {committed_.data() + p * stride(), history_};
  }

  /// The trial state becomes the committed state.
  void commit();
  /// The trial state is thrown away (it is reset to the committed state).
  void revert();
  /// Trial = committed for points [first, last) (points that are not evaluated, e.g. of
  /// inactive cells, so that commit() keeps their state).
  void hold(std::size_t first, std::size_t last);
  /// Replaces the committed and trial states (restart); `committed` must have the store's size.
  void restore(const std::vector<double>& committed);

  [[nodiscard]] const std::vector<double>& committed_data() const { return committed_; }
  [[nodiscard]] const std::vector<double>& trial_data() const { return trial_; }

private:
  std::size_t points_ = 0;
  int history_ = 0;
  std::vector<double> committed_, trial_;
};

} // namespace stratum
