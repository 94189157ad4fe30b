// The C++ options structs as the command line's flags: the bridge parses them with the
// command line's own definitions, so an option means exactly what its flag means, with
// the same checks and messages. Messages name the flag: `--tile-size` is the option
// `.tile_size`.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "rust/cxx.h"

namespace asperity::impl {

/// `--name=value` flags, values written so that they read back exactly.
class Flags {
 public:
  template <class T>
  Flags& add(const char* name, const T& value) {
    std::ostringstream text;
    text.precision(std::numeric_limits<double>::max_digits10);
    text << "--" << name << '=';
    write(text, value);
    flags_.emplace_back(text.str());
    return *this;
  }
  template <class T>
  Flags& add(const char* name, const std::optional<T>& value) {
    return value ? add(name, *value) : *this;
  }
  Flags& add_switch(const char* name, bool on) {
    if (on) flags_.emplace_back(std::string("--") + name);
    return *this;
  }
  const rust::Vec<rust::String>& get() const { return flags_; }

 private:
  static void write(std::ostringstream& text, const std::string& value) { text << value; }
  static void write(std::ostringstream& text, const char* value) { text << value; }
  static void write(std::ostringstream& text, double value) { text << value; }
  static void write(std::ostringstream& text, std::uint64_t value) { text << value; }
  static void write(std::ostringstream& text, std::uint32_t value) { text << value; }
  template <class T, std::size_t N>
  static void write(std::ostringstream& text, const std::array<T, N>& values) {
    for (std::size_t i = 0; i < N; ++i) {
      if (i) text << ',';
      write(text, values[i]);
    }
  }
  rust::Vec<rust::String> flags_;
};

}  // namespace asperity::impl
