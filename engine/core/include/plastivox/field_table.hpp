// What a list of fields generates (state.hpp's PLASTIVOX_STATE_FIELDS, in the manner of
// MuJoCo's X-macro lists for mjData): a struct's members, their values at t = 0, and a table
// of rows (name, shape, unit, axes, meaning, bytes) that drives saving, restoring and
// hashing, and the Python module's views. A list is a macro of three macros:
//   FIELD(type, name, initial, shape, unit, axes, meaning): a member and its row;
//   MEMBER(type, name, initial): a member whose rows are listed apart (one per component);
//   ROW(name, member, shape, unit, axes, meaning): a row of `member` (an expression such as
//       bond_prev[0]).
// `initial` is an expression of the model `m`. Shapes: "1" one value, "3" a fixed vector,
// "n" per voxel, "n x 3" a vector per voxel, "n x 4" a quaternion per voxel (x, y, z, w:
// Eigen's order), "bonds" per bond, "memory" as many as the controller keeps.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace plastivox {

// Where a row's values are.
struct StateFieldBytes {
  const void* data = nullptr;
  size_t count = 0;        // values (doubles, bytes or integers), all components included
  size_t value_bytes = 0;  // bytes per value
  char kind = 'f';         // what a value is: 'f' floating point, 'i' signed integer (or an
                           // enum), 'u' unsigned integer, 'b' bool
  size_t width = 1;        // values per entry: 3 for a vector, 4 for a quaternion, else 1
};

// One row of a table over the struct S.
template <class S>
struct FieldRow {
  const char* name;
  const char* shape;
  const char* unit;
  const char* axes;
  const char* meaning;
  StateFieldBytes (*bytes)(const S&);
};

namespace fields {

template <class T>
constexpr char kind_of() {
  if constexpr (std::is_same_v<T, bool>) return 'b';
  if constexpr (std::is_floating_point_v<T>) return 'f';
  if constexpr (std::is_enum_v<T> || std::is_signed_v<T>) return 'i';
  return 'u';
}

// A member's bytes: one value, a vector of values, an array of them, or Eigen's fixed-size
// vectors and quaternions (plain arrays of doubles, so a vector of them is one flat array).
template <class T>
StateFieldBytes bytes_of(const T& v) {
  if constexpr (std::is_base_of_v<Eigen::MatrixBase<T>, T>) {
    constexpr size_t k = sizeof(T) / sizeof(double);
    return {v.data(), k, sizeof(double), 'f', k};
  } else {
    static_assert(std::is_arithmetic_v<T> || std::is_enum_v<T>);
    return {&v, 1, sizeof v, kind_of<T>(), 1};
  }
}
template <class T>
StateFieldBytes bytes_of(const std::vector<T>& v) {
  if constexpr (std::is_arithmetic_v<T>) {
    return {v.data(), v.size(), sizeof(T), kind_of<T>(), 1};
  } else {  // Eigen's Vector3d, Quaterniond
    constexpr size_t k = sizeof(T) / sizeof(double);
    static_assert(sizeof(T) == k * sizeof(double));
    return {v.data(), v.size() * k, sizeof(double), 'f', k};
  }
}
template <class T, size_t kSize>
StateFieldBytes bytes_of(const std::array<T, kSize>& v) {
  return {v.data(), kSize, sizeof(T), kind_of<T>(), 1};
}
template <class T, size_t kSize>
StateFieldBytes bytes_of(const T (&v)[kSize]) {
  return {v, kSize, sizeof(T), kind_of<T>(), 1};
}

// A member's value before make_initial_state sets it (Eigen leaves its vectors unset).
template <class T>
T zero() {
  if constexpr (std::is_base_of_v<Eigen::MatrixBase<T>, T>)
    return T::Zero();
  else
    return T{};
}

// The byte layer under save, restore and hash, for any table: a row's bytes as the struct
// holds them now.
struct View {
  const char* name;
  StateFieldBytes bytes;
};
template <class S>
std::vector<View> views(const std::vector<FieldRow<S>>& table, const S& s) {
  std::vector<View> out;
  out.reserve(table.size());
  for (const FieldRow<S>& row : table) out.push_back({row.name, row.bytes(s)});
  return out;
}
// 64-bit FNV-1a of every row in order: its value count, then its bytes.
uint64_t hash(const std::vector<View>& rows);
// A header, then every row as its value count, value size and bytes, then `text`.
std::vector<uint8_t> save(const std::vector<View>& rows, std::string_view text);
// Checks `snapshot` against the rows (every count and value size, bools 0 or 1, nothing
// missing or past the end): where each row's bytes are in it, and the text. Throws
// std::invalid_argument naming the row on any difference; reads nothing into the struct.
struct Read {
  std::vector<const uint8_t*> from;
  std::string text;
};
Read check(const std::vector<View>& rows, const std::vector<uint8_t>& snapshot);
// Copies the checked bytes into the struct's own arrays (which keep their storage).
void copy(const std::vector<View>& rows, const Read& read);

}  // namespace fields
}  // namespace plastivox

// The generators, each applied to a list.
#define PLASTIVOX_FIELD_DECLARE(type, name, initial, shape, unit, axes, meaning) \
  type name = ::plastivox::fields::zero<type>();
#define PLASTIVOX_MEMBER_DECLARE(type, name, initial) type name = ::plastivox::fields::zero<type>();
#define PLASTIVOX_FIELD_INITIAL(type, name, initial, shape, unit, axes, meaning) s.name = initial;
#define PLASTIVOX_MEMBER_INITIAL(type, name, initial) s.name = initial;
#define PLASTIVOX_ROW_ENTRY(name, member, shape, unit, axes, meaning) \
  {#name, shape,   unit,                                              \
   axes,  meaning, [](const auto& s) { return ::plastivox::fields::bytes_of(s.member); }},
#define PLASTIVOX_FIELD_ROW(type, name, initial, shape, unit, axes, meaning) \
  PLASTIVOX_ROW_ENTRY(name, name, shape, unit, axes, meaning)
#define PLASTIVOX_NO_MEMBER(type, name, initial)
#define PLASTIVOX_NO_ROW(name, member, shape, unit, axes, meaning)

// The members of a struct (inside its braces).
#define PLASTIVOX_MEMBERS(LIST) \
  LIST(PLASTIVOX_FIELD_DECLARE, PLASTIVOX_MEMBER_DECLARE, PLASTIVOX_NO_ROW)
// Statements setting every member of `s` from the model `m`.
#define PLASTIVOX_INITIAL_VALUES(LIST) \
  LIST(PLASTIVOX_FIELD_INITIAL, PLASTIVOX_MEMBER_INITIAL, PLASTIVOX_NO_ROW)
// The rows, as the braced initialiser of a std::vector<FieldRow<S>>.
#define PLASTIVOX_ROWS(LIST) \
  { LIST(PLASTIVOX_FIELD_ROW, PLASTIVOX_NO_MEMBER, PLASTIVOX_ROW_ENTRY) }
