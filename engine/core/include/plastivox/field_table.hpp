// What a list of fields generates (state.hpp's PLASTIVOX_STATE_FIELDS, in the manner of
// MuJoCo's X-macro lists for mjData): a struct's members, their values at t = 0, a table of
// rows (name, shape, unit, axes, meaning, bytes) that drives saving, restoring and hashing,
// and the Python module's views, the kernels' views of the rows' arrays, and the members and
// channel table of a recorded frame. A list is a macro of four macros:
//   FIELD(type, name, initial, views, shape, unit, axes, meaning): a member and its row;
//   RECORDED(type, name, initial, views, shape, unit, axes, meaning, dataset, python): a FIELD
//       that every recorded frame also copies, as the channel `dataset` of a recorded life
//       file and the attribute `python` of a Python Trajectory;
//   MEMBER(type, name, initial, views): a member whose rows are listed apart (one per
//       component);
//   ROW(name, member, shape, unit, axes, meaning): a row of `member` (an expression such as
//       bond_prev[0]).
// `initial` is an expression of the model `m`. `views` is a parenthesised list of the
// kernels' pointers to the member's array, named through `views` (a KernelViews,
// engine/core/src/workspace.hpp), such as (views.voxel.pos, views.voxel_out.pos); () for
// none; a MEMBER's are arrays of pointers, one per component. Shapes: "1" one value, "3" a fixed
// vector, "n" per voxel, "n x 3" a vector per voxel, "n x 4" a quaternion per voxel (x, y, z, w:
// Eigen's order), "bonds" per bond, "memory" as many as the controller keeps.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <tuple>
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

// One channel of a recorded frame F, copied from a RECORDED row of the struct S: `width`
// doubles per voxel; outside the engine an array (frames, voxels[, width]) with its
// components in `order` (the quaternion w first, as the file formats hold it).
template <class S, class F>
struct FrameRow {
  const char* name;                   // dataset in a recorded life file
  const char* python;                 // attribute of a Python Trajectory
  const char* state_field;            // the row of S it copies
  int width;                          // doubles per voxel
  int order[4];                       // the array's component k is the frame's component order[k]
  const double* (*values)(const F&);  // the frame's voxels x width doubles
  void (*resize)(F&, size_t voxels);
  void (*copy)(const S&, F&);  // the row of s into the frame (null: not a row of S)
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

// A per-voxel array as the flat array of numbers the kernels read (x, y, z per vector; x, y, z,
// w per quaternion), or nullptr when empty.
template <class V>
auto* data_of(V& v) {
  using T = typename std::remove_const_t<V>::value_type;
  if constexpr (std::is_arithmetic_v<T>) {
    return v.data();
  } else if constexpr (std::is_base_of_v<Eigen::QuaternionBase<T>, T>) {
    return v.empty() ? nullptr : v.front().coeffs().data();
  } else {
    return v.empty() ? nullptr : v.front().data();
  }
}

// Points a view at a member's array (or an array of views at the arrays of a member's
// components), or says whether it points there.
template <class P, class M>
void point_one(P& view, M& member) {
  view = data_of(member);
}
template <class P, size_t kSize, class M>
void point_one(P (&view)[kSize], std::array<M, kSize>& member) {
  for (size_t k = 0; k < kSize; ++k) view[k] = data_of(member[k]);
}
template <class P, class M>
bool points_at_one(const P& view, const M& member) {
  return view == data_of(member);
}
template <class P, size_t kSize, class M>
bool points_at_one(const P (&view)[kSize], const std::array<M, kSize>& member) {
  for (size_t k = 0; k < kSize; ++k)
    if (view[k] != data_of(member[k])) return false;
  return true;
}
// The same for every view of `views` (a std::tie of the kernels' pointers; none for ()).
template <class Views, class M>
void point(Views views, M& member) {
  if constexpr (std::tuple_size_v<Views> != 0)
    std::apply([&](auto&... view) { (point_one(view, member), ...); }, views);
}
template <class Views, class M>
bool points_at(Views views, const M& member) {
  if constexpr (std::tuple_size_v<Views> != 0)
    return std::apply([&](const auto&... view) { return (points_at_one(view, member) && ...); },
                      views);
  return true;
}

// A recorded channel's doubles per voxel, and where the file's component k is in a voxel's
// (a quaternion is x, y, z, w here and w, x, y, z in the files).
template <class V>
constexpr int width_of() {
  return static_cast<int>(sizeof(typename V::value_type) / sizeof(double));
}
template <class V>
constexpr int file_component(int k) {
  return width_of<V>() == 4 ? (k + 3) % 4 : k;
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

// The generators, each applied to a list. One macro serves FIELD, RECORDED and MEMBER where
// they agree: the arguments past those it names are ignored.
#define PLASTIVOX_IGNORE(...)
#define PLASTIVOX_DECLARE(type, name, ...) type name = ::plastivox::fields::zero<type>();
#define PLASTIVOX_INITIAL(type, name, initial, ...) s.name = initial;
#define PLASTIVOX_ROW_ENTRY(name, member, shape, unit, axes, meaning) \
  {#name, shape,   unit,                                              \
   axes,  meaning, [](const auto& s) { return ::plastivox::fields::bytes_of(s.member); }},
#define PLASTIVOX_FIELD_ROW(type, name, initial, views, shape, unit, axes, meaning, ...) \
  PLASTIVOX_ROW_ENTRY(name, name, shape, unit, axes, meaning)
#define PLASTIVOX_BIND(type, name, initial, views, ...) \
  ::plastivox::fields::point(std::tie views, s.name);
#define PLASTIVOX_BOUND(type, name, initial, views, ...) \
  &&::plastivox::fields::points_at(std::tie views, s.name)
#define PLASTIVOX_FRAME_CHANNEL(type, name, initial, views, shape, unit, axes, meaning, dataset, \
                                python)                                                          \
  {dataset,                                                                                      \
   python,                                                                                       \
   #name,                                                                                        \
   ::plastivox::fields::width_of<type>(),                                                        \
   {::plastivox::fields::file_component<type>(0), ::plastivox::fields::file_component<type>(1),  \
    ::plastivox::fields::file_component<type>(2), ::plastivox::fields::file_component<type>(3)}, \
   [](const auto& f) { return ::plastivox::fields::data_of(f.name); },                           \
   [](auto& f, size_t voxels) { f.name.resize(voxels); },                                        \
   [](const auto& s, auto& f) { f.name = s.name; }},

// The members of a struct (inside its braces).
#define PLASTIVOX_MEMBERS(LIST) \
  LIST(PLASTIVOX_DECLARE, PLASTIVOX_DECLARE, PLASTIVOX_DECLARE, PLASTIVOX_IGNORE)
// Statements setting every member of `s` from the model `m`.
#define PLASTIVOX_INITIAL_VALUES(LIST) \
  LIST(PLASTIVOX_INITIAL, PLASTIVOX_INITIAL, PLASTIVOX_INITIAL, PLASTIVOX_IGNORE)
// The rows, as the braced initialiser of a std::vector<FieldRow<S>>.
#define PLASTIVOX_ROWS(LIST) \
  { LIST(PLASTIVOX_FIELD_ROW, PLASTIVOX_FIELD_ROW, PLASTIVOX_IGNORE, PLASTIVOX_ROW_ENTRY) }
// Statements pointing every view the list names (through `views`) at its array in `s`.
#define PLASTIVOX_BIND_VIEWS(LIST) \
  LIST(PLASTIVOX_BIND, PLASTIVOX_BIND, PLASTIVOX_BIND, PLASTIVOX_IGNORE)
// An expression: whether every view the list names points at its array in `s`.
#define PLASTIVOX_VIEWS_BOUND(LIST) \
  (true LIST(PLASTIVOX_BOUND, PLASTIVOX_BOUND, PLASTIVOX_BOUND, PLASTIVOX_IGNORE))
// The members of a recorded frame (inside its braces): the RECORDED rows, typed as in the
// struct.
#define PLASTIVOX_FRAME_MEMBERS(LIST) \
  LIST(PLASTIVOX_IGNORE, PLASTIVOX_DECLARE, PLASTIVOX_IGNORE, PLASTIVOX_IGNORE)
// The frame's channels, as the braced initialiser of a std::vector<FrameRow<S, F>>.
#define PLASTIVOX_FRAME_CHANNELS(LIST) \
  { LIST(PLASTIVOX_IGNORE, PLASTIVOX_FRAME_CHANNEL, PLASTIVOX_IGNORE, PLASTIVOX_IGNORE) }
