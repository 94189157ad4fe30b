// Progress and cancellation for long calls: a function (stage, done, total) that asperity
// calls at each progress report of a build or a refinement; returning false stops the call,
// which then throws asperity::Cancelled and leaves nothing half-built. An exception the
// function throws stops the call too and arrives unchanged (it never crosses into Rust:
// the bridge's callback catches it and rethrows it after the call).
#pragma once

#include <cstdint>
#include <exception>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>

#include "rust/cxx.h"

namespace asperity {

/// Called at each progress report: `stage` has done `done` of `total` steps. Return false
/// to stop the call (it throws asperity::Cancelled).
using ProgressFunction = std::function<bool(const std::string& stage, std::uint64_t done, std::uint64_t total)>;

/// A call stopped by its progress function.
class Cancelled : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace ffi {

/// The bridge's view of a ProgressFunction (asperity's own type: use ProgressFunction).
class ProgressCallback {
 public:
  explicit ProgressCallback(ProgressFunction function = {}) : function_(std::move(function)) {}

  /// Whether a function is watching (without one, the call runs unwatched).
  bool watching() const noexcept { return bool(function_); }

  /// The function's answer to one report; an exception it throws is kept for
  /// rethrow_if_thrown() and stops the call.
  bool report(rust::Str stage, std::uint64_t done, std::uint64_t total) const noexcept {
    try {
      return function_(std::string(stage), done, total);
    } catch (...) {
      thrown_ = std::current_exception();
      return false;
    }
  }

  /// Rethrows what the function threw, if it threw.
  void rethrow_if_thrown() const {
    if (thrown_) std::rethrow_exception(thrown_);
  }

 private:
  ProgressFunction function_;
  mutable std::exception_ptr thrown_;
};

}  // namespace ffi
}  // namespace asperity
