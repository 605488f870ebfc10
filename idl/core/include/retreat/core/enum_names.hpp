#pragma once
/// @file
/// One name table per enum: how a scenario file, a dump and an error message spell its values.
/// An enum `E` opts in by declaring, in its own namespace, `constexpr EnumNames<E, N>
/// enum_names(E)` (found by argument-dependent lookup); the scenario loaders, the dumps and the
/// programs' messages all read that one table. Strings live at the edges; code compares enums.

#include <array>
#include <concepts>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

namespace retreat {

/// The names of the N values of enum @p E, in the order messages list them.
template <class E, std::size_t N>
struct EnumNames {
  std::array<std::pair<E, std::string_view>, N> entries;
  /// What a bad name is told after "must be "; empty: "one of <the names, comma-separated>".
  std::string_view rule = {};

  /// The value named @p name, if any (names are case-sensitive, as in scenario files).
  [[nodiscard]] constexpr std::optional<E> find(std::string_view name) const {
    for (const auto& [value, text] : entries) {
      if (text == name) return value;
    }
    return std::nullopt;
  }

  /// The name of @p value; "?" for a value outside the table (a cast, never a parsed value).
  [[nodiscard]] constexpr std::string_view name(E value) const {
    for (const auto& [v, text] : entries) {
      if (v == value) return text;
    }
    return "?";
  }

  /// What is allowed, as an error message ends: `one of ellipse, rectangle` (or `rule`).
  [[nodiscard]] std::string allowed() const {
    if (!rule.empty()) return std::string(rule);
    std::string out = "one of ";
    for (std::size_t i = 0; i < N; ++i) {
      out += (i == 0 ? "" : ", ") + std::string(entries[i].second);
    }
    return out;
  }
};

/// An enum with a name table (see the file comment).
template <class E>
concept NamedEnum = std::is_enum_v<E> && requires(E e) {
  { enum_names(e).find(std::string_view{}) } -> std::same_as<std::optional<E>>;
};

/// The name of @p value, e.g. `name_of(DomainShape::ellipse)` is "ellipse".
template <NamedEnum E>
constexpr std::string_view name_of(E value) {
  return enum_names(value).name(value);
}

/// The value named @p name, or nothing.
template <NamedEnum E>
constexpr std::optional<E> value_of(std::string_view name) {
  return enum_names(E{}).find(name);
}

}  // namespace retreat
