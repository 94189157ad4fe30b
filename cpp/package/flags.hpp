// The C++ options structs as the library's request fields (`Fields`, a JSON object the
// bridge reads strictly into the request: noise) or, where no request exists yet (#38),
// as the command line's flags (`Flags`, parsed with the command line's own definitions).
// Either way an option means what its flag means, with the same checks; messages name
// the option: `.tile_size`.
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

/// A JSON object of a library request's fields (`"octaves": 6`): the bridge reads the
/// request from it with strict keys, and its checks name a field as the option `.octaves`.
/// Unset optionals are left out, so they take the library's defaults.
class Fields {
 public:
  template <class T>
  Fields& add(const char* name, const T& value) {
    text_ << (empty_ ? "{" : ",") << '"' << name << "\":";
    empty_ = false;
    write(value);
    return *this;
  }
  template <class T>
  Fields& add(const char* name, const std::optional<T>& value) {
    return value ? add(name, *value) : *this;
  }
  std::string json() const { return empty_ ? "{}" : text_.str() + "}"; }

 private:
  void write(const std::string& value) {
    text_ << '"';
    for (char c : value) {
      if (c == '"' || c == '\\') {
        text_ << '\\' << c;
      } else if (static_cast<unsigned char>(c) < 0x20) {
        text_ << "\\u00" << "0123456789abcdef"[(c >> 4) & 0xf] << "0123456789abcdef"[c & 0xf];
      } else {
        text_ << c;
      }
    }
    text_ << '"';
  }
  void write(const char* value) { write(std::string(value)); }
  void write(bool value) { text_ << (value ? "true" : "false"); }
  void write(double value) {
    text_.precision(std::numeric_limits<double>::max_digits10);
    // JSON has no NaN or infinity: a string, which the bridge names as the wrong type.
    if (value != value || value - value != 0.0) {
      text_ << '"' << value << '"';
    } else {
      text_ << value;
    }
  }
  void write(std::uint64_t value) { text_ << value; }
  void write(std::uint32_t value) { text_ << value; }
  std::ostringstream text_;
  bool empty_ = true;
};

}  // namespace asperity::impl
