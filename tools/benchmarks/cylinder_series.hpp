// The series of meshes of the thick-walled cylinder that bench_linear, bench_scaling and bench_ccx
// measure (an nx x nx/2 grid of quad8 cells over the 1 x 0.5 section), and the clocks they read.
#pragma once

#include <chrono>
#include <ctime>

namespace stratum::bench {

/// One mesh of the series: the requested size and the nx x ny cells reaching it.
struct Size {
  double target = 0;
  int nx = 0, ny = 0;
};

/// Free unknowns of an nx x nx/2 quad8 mesh with u_z fixed on top and bottom:
/// 2 (1.5 nx^2 + 3 nx + 1) DOF less 2 (2 nx + 1) constrained ones (the same count for the
/// quarter ring with u_y fixed at theta = 0 and u_x at theta = 90 deg).
inline long long free_dofs(long long nx) { return 3 * nx * nx + 2 * nx; }

/// Smallest even nx (cells square: ny = nx / 2 over a 1 x 0.5 section) with at least `target` free DOF.
inline Size size_for(double target) {
  int nx = 2;
  while (static_cast<double>(free_dofs(nx)) < target) nx += 2;
  return {target, nx, nx / 2};
}

using Clock = std::chrono::steady_clock;

/// Wall time since t0 in seconds.
inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// CPU time of the whole process (all threads, user + system): unlike wall time it hardly
/// grows when other processes compete for the cores.
inline double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

} // namespace stratum::bench
