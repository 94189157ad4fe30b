// The C++ options structs as the library's request fields (`Fields`, a JSON object the
// bridge reads strictly into the request, #38): an option means what its flag means, with
// the same checks; messages name the option: `option .tile_size`.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

namespace asperity::impl {

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
  template <class T, std::size_t N>
  void write(const std::array<T, N>& values) {
    text_ << '[';
    for (std::size_t i = 0; i < N; ++i) {
      if (i) text_ << ',';
      write(values[i]);
    }
    text_ << ']';
  }
  std::ostringstream text_;
  bool empty_ = true;
};

}  // namespace asperity::impl
