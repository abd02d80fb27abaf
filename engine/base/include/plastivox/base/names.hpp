// An enum's names, written once as a table of {value, name} rows: the table prints a value,
// parses a name and lists the choices in an error message, so the three cannot drift apart.
//
//   constexpr Named<Colour> kColourNames[] = {{Colour::kRed, "red"}, {Colour::kBlue, "blue"}};
//   const char* to_string(Colour c) { return name_in(kColourNames, c); }
//
// Header only; the tables are constexpr arrays, searched in order (they are short).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace plastivox {

template <class E>
struct Named {
  E value;
  const char* name;
};

// The name of v, or "?" for a value the table lacks.
template <class E, size_t N>
constexpr const char* name_in(const Named<E> (&table)[N], E v) {
  for (const Named<E>& row : table)
    if (row.value == v) return row.name;
  return "?";
}

// The value named s, or nothing.
template <class E, size_t N>
constexpr std::optional<E> value_in(const Named<E> (&table)[N], std::string_view s) {
  for (const Named<E>& row : table)
    if (s == row.name) return row.value;
  return std::nullopt;
}

// The names for an error message: "a, b or c" (quoted: "\"a\", \"b\" or \"c\"").
template <class E, size_t N>
std::string choices_in(const Named<E> (&table)[N], bool quoted = false) {
  std::string out;
  for (size_t i = 0; i < N; ++i) {
    if (i > 0) out += i + 1 < N ? ", " : " or ";
    if (quoted) out += '"';
    out += table[i].name;
    if (quoted) out += '"';
  }
  return out;
}

}  // namespace plastivox
