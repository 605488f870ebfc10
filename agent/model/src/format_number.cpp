#include "retreat/model/format_number.hpp"

#include <array>
#include <charconv>
#include <cmath>

namespace retreat::model {

std::string format_number(double value) {
  if (std::isnan(value)) {
    return "nan";
  }
  if (std::isinf(value)) {
    return value > 0 ? "inf" : "-inf";
  }
  // Shortest round-trip form (C++17 <charconv>); 32 characters hold any double.
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

}  // namespace retreat::model
