// asperity's errors in C++: every call of the package throws asperity::InputError (bad
// input: a mesh, a recipe or an option asperity cannot use; the command line's exit 2) or
// asperity::InternalError (a failure inside asperity or its native libraries; exit 1),
// with the command line's one-line message. Both derive from std::runtime_error.
#pragma once

#include <stdexcept>
#include <string>

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
/// with its exit code and a bar: "2|…" is bad input, anything else internal.
[[noreturn]] inline void rethrow(const rust::Error& error) {
  const std::string message = error.what();
  const auto bar = message.find('|');
  const std::string text = bar == std::string::npos ? message : message.substr(bar + 1);
  if (bar != std::string::npos && message.compare(0, bar, "2") == 0) throw InputError(text);
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

}  // namespace impl
}  // namespace asperity
