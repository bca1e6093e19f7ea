// Wall-time accounting of a run (RunTimes): internal to the run loop.
#pragma once

#include <chrono>

namespace stratum {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Runs f() and adds its wall time to `seconds`; returns what f returns.
template <class F> decltype(auto) timed(double& seconds, F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  struct Add {
    double& s;
    std::chrono::steady_clock::time_point t0;
    ~Add() { s += seconds_since(t0); }
  } add{seconds, t0};
  return f();
}

} // namespace stratum
