// asperity's errors in C++: every call of the package throws asperity::InputError (bad
// input: a mesh, a recipe or an option asperity cannot use; the command line's exit 2) or
// asperity::InternalError (a failure inside asperity or its native libraries; exit 1),
// with the command line's one-line message, or asperity::Cancelled (progress.hpp: the
// call's progress function said stop). All derive from std::runtime_error.
#pragma once

#include <stdexcept>
#include <string>

#include "asperity/progress.hpp"
#include "rust/cxx.h"

namespace asperity {

/// Bad input: a mesh, a recipe or an option asperity cannot use (the command line's exit 2).
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A failure inside asperity or its native libraries (the command line's exit 1).
class InternalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace impl {

/// Rethrows a bridge error as its typed exception. The Rust side prefixes every message
/// with its exit code and a bar: "2|…" is bad input, "130|…" a cancellation, anything
/// else internal.
[[noreturn]] inline void rethrow(const rust::Error& error) {
  const std::string message = error.what();
  const auto bar = message.find('|');
  const std::string text = bar == std::string::npos ? message : message.substr(bar + 1);
  const std::string code = bar == std::string::npos ? "" : message.substr(0, bar);
  if (code == "2") throw InputError(text);
  if (code == "130") throw Cancelled(text);
  throw InternalError(text);
}

/// Runs a bridge call, turning its error into the typed exception.
template <class Call>
decltype(auto) call(Call&& bridge_call) {
  try {
    return bridge_call();
  } catch (const rust::Error& error) {
    rethrow(error);
  }
}

/// A bridge call watched by a progress function: what the function threw comes first, as
/// it was thrown; then the call's own error.
template <class Call>
decltype(auto) call(const ffi::ProgressCallback& progress, Call&& bridge_call) {
  try {
    return bridge_call();
  } catch (const rust::Error& error) {
    progress.rethrow_if_thrown();
    rethrow(error);
  }
}

}  // namespace impl
}  // namespace asperity
