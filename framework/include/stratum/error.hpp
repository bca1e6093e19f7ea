// Errors and statuses of Stratum.
//
// Two kinds of trouble, kept apart on purpose:
//  * bad input or a broken environment -> stratum::Error (an exception), carrying a
//    message and, where the trouble came from the scene file, file:line:col;
//  * numerical trouble during a run (no convergence, failed return mapping,
//    NaN) -> an Outcome value that flows back to the step driver.
#pragma once

#include <stdexcept>
#include <string>

namespace stratum {

/// Where a value came from in an input file. line/column are 1-based; 0 means unknown.
struct SourceLocation {
  std::string file;
  int line = 0;
  int column = 0;

  [[nodiscard]] bool known() const { return !file.empty(); }
  /// "file:line:col", "file" or "" depending on what is known.
  [[nodiscard]] std::string str() const;
};

/// The one exception type of Stratum. what() is the complete one-line message,
/// prefixed with "file:line:col " when the location is known.
class Error : public std::runtime_error {
public:
  explicit Error(const std::string& message);
  Error(SourceLocation where, const std::string& message);

  [[nodiscard]] const SourceLocation& where() const { return where_; }
  [[nodiscard]] const std::string& message() const { return message_; }

private:
  SourceLocation where_;
  std::string message_;
};

/// Result category of a numerical operation.
enum class Status {
  ok,
  not_converged,    ///< an iteration (local or global) ran out of iterations
  material_failure, ///< a constitutive update could not find a stress
  singular,         ///< a linear system could not be factorized
  non_finite,       ///< NaN or Inf appeared
  diverged,         ///< residual grew beyond a safe bound
  /// Not numerical and not worth a retry: the step driver stops the run at once (no cut-back)
  /// with the message, keeping the results written so far. For a configuration error found only
  /// when a point is evaluated (e.g. a UMAT writing past NSTATV) or a model that asks to end the
  /// analysis (a UMAT calling XIT).
  fatal,
};

[[nodiscard]] const char* to_string(Status s);

/// A status with a human-readable message naming the failing place.
struct Outcome {
  Status status = Status::ok;
  std::string message;

  [[nodiscard]] bool ok() const { return status == Status::ok; }
  [[nodiscard]] static Outcome success() { return {}; }
  [[nodiscard]] static Outcome failure(Status s, std::string msg) { return {s, std::move(msg)}; }
};

} // namespace stratum
