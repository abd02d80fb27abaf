// Thin, checked wrappers over the HDF5 C API, for the results file, analysis.h5 and lives.
//
// Every call's return value is checked; a failure throws ResultsError with one line that
// names the file and the object. HDF5's own error printing is switched off
// (quiet_hdf5()), so a corrupt, truncated or foreign file produces our message and nothing
// else. HDF5 (Debian's serial build) is not thread-safe: call these from one thread only.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "plastivox/base/error.hpp"  // ResultsError

namespace plastivox::h5 {

void quiet_hdf5();  // turn off HDF5's automatic error printing (idempotent)

// Owns one hid_t and closes it with the right H5*close.
class Handle {
 public:
  enum class Kind { kFile, kGroup, kDataset, kDataspace, kDatatype, kAttribute, kPlist };
  Handle() = default;
  Handle(hid_t id, Kind kind) : id_(id), kind_(kind) {}
  Handle(Handle&& o) noexcept : id_(o.id_), kind_(o.kind_) { o.id_ = -1; }
  Handle& operator=(Handle&& o) noexcept;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }
  hid_t id() const { return id_; }
  void reset();
  herr_t close();  // explicit close, for files, to check the final flush

 private:
  hid_t id_ = -1;
  Kind kind_ = Kind::kFile;
};

// Context for error messages: the file path.
struct Ctx {
  std::string file;
  uint64_t file_size = 0;  // bytes; bounds every read (0 = no bound, when writing)
  [[noreturn]] void fail(const std::string& object, const std::string& what) const;
};

// The context for reading the file at `path`, bounded by its size; quiets HDF5 first.
// Throws ResultsError "<path>: no such file" or "<path>: not a regular file".
Ctx read_context(const std::string& path);

// An HDF5 file built in memory (the core driver, no backing store). Why: when HDF5 itself
// writes to a full disk, a failed flush can leave the file half-closed inside the library,
// which then faults while closing it again at exit. Built in memory, nothing HDF5 does can
// fail for lack of disk; the caller writes image() with checked POSIX writes. Every handle
// is a Handle, so an exception on any path closes everything it opened.
class MemoryFile {
 public:
  // user_block: bytes reserved before the HDF5 superblock (0 or a power of two >= 512).
  MemoryFile(const Ctx& c, hsize_t user_block);
  hid_t id() const { return file_.id(); }
  // The file's bytes: `user_block` zero bytes, then the HDF5 image. Closes the file; every
  // object opened in it must be closed first.
  std::string image();

 private:
  Ctx c_;
  hsize_t user_block_;
  Handle file_;
};

Handle create_group(const Ctx& c, hid_t loc, const std::string& name);
Handle open_group(const Ctx& c, hid_t loc, const std::string& name);
bool has_link(hid_t loc, const std::string& name);

// Element types: uint8, int32, int64, uint64, double.
template <class T>
void write(const Ctx& c, hid_t loc, const std::string& name, const std::vector<T>& data,
           const std::vector<hsize_t>& dims);
template <class T>
void write(const Ctx& c, hid_t loc, const std::string& name, const std::vector<T>& data) {
  write(c, loc, name, data, {static_cast<hsize_t>(data.size())});
}
// Reads a dataset of rank dims.size(); every entry of `dims` that is not kAnyExtent must
// match. Returns the data; `dims` receives the actual extents.
constexpr hsize_t kAnyExtent = ~hsize_t{0};
template <class T>
std::vector<T> read(const Ctx& c, hid_t loc, const std::string& name, std::vector<hsize_t>& dims);
template <class T>
std::vector<T> read(const Ctx& c, hid_t loc, const std::string& name, hsize_t n) {
  std::vector<hsize_t> dims = {n};
  return read<T>(c, loc, name, dims);
}

// Strings (datasets and attributes) are written as variable-length UTF-8, which h5py reads
// as str; readers also accept fixed-length ASCII or UTF-8 strings (files written before).
void write_strings(const Ctx& c, hid_t loc, const std::string& name,
                   const std::vector<std::string>& s);
std::vector<std::string> read_strings(const Ctx& c, hid_t loc, const std::string& name, hsize_t n);

// A table of records stored as columns (the results file's /individuals, analysis.h5's
// /inputs, ...): the dataset `name` holds get(row) (a function or a data member), as a T, for
// every row in order.
template <class T, class Row, class Get>
void write_column(const Ctx& c, hid_t loc, const std::string& name, const std::vector<Row>& rows,
                  const Get& get) {
  std::vector<T> column;
  column.reserve(rows.size());
  for (const Row& r : rows) column.push_back(static_cast<T>(std::invoke(get, r)));
  if constexpr (std::is_same_v<T, std::string>)
    write_strings(c, loc, name, column);
  else
    write(c, loc, name, column);
}
// The same for a data member, stored as its own type: write_column(c, g, "id", rows, &Row::id).
template <class Row, class T>
void write_column(const Ctx& c, hid_t loc, const std::string& name, const std::vector<Row>& rows,
                  T Row::*member) {
  write_column<T>(c, loc, name, rows, member);
}

// The reverse: the dataset `name`, which must hold rows.size() entries, into each row's
// `member`, in order.
template <class Row, class T>
void read_column(const Ctx& c, hid_t loc, const std::string& name, std::vector<Row>& rows,
                 T Row::*member) {
  std::vector<T> column;
  if constexpr (std::is_same_v<T, std::string>)
    column = read_strings(c, loc, name, rows.size());
  else
    column = read<T>(c, loc, name, rows.size());
  for (size_t i = 0; i < rows.size(); ++i) rows[i].*member = std::move(column[i]);
}

void write_attr(const Ctx& c, hid_t obj, const std::string& name, const std::string& value);
void write_attr(const Ctx& c, hid_t obj, const std::string& name, int64_t value);
void write_attr_u64(const Ctx& c, hid_t obj, const std::string& name, uint64_t value);
void write_attr(const Ctx& c, hid_t obj, const std::string& name, double value);
bool has_attr(hid_t obj, const std::string& name);
// The string attribute "units" on the dataset `dataset` in `loc` ("m", "s", "Pa", "voxel
// lengths", "1" for a dimensionless quantity). Readers do not need it: files without it read.
void write_units(const Ctx& c, hid_t loc, const std::string& dataset, const std::string& units);
std::string read_attr_string(const Ctx& c, hid_t obj, const std::string& where,
                             const std::string& name);
int64_t read_attr_int(const Ctx& c, hid_t obj, const std::string& where, const std::string& name);
uint64_t read_attr_u64(const Ctx& c, hid_t obj, const std::string& where, const std::string& name);
double read_attr_double(const Ctx& c, hid_t obj, const std::string& where, const std::string& name);
// The same, chosen by the type of `out`: for code that visits a struct's fields
// (for_each_field in provenance.hpp) and writes them with the write_attr overloads.
inline void read_attr(const Ctx& c, hid_t obj, const std::string& where, const std::string& name,
                      std::string& out) {
  out = read_attr_string(c, obj, where, name);
}
inline void read_attr(const Ctx& c, hid_t obj, const std::string& where, const std::string& name,
                      int64_t& out) {
  out = read_attr_int(c, obj, where, name);
}
inline void read_attr(const Ctx& c, hid_t obj, const std::string& where, const std::string& name,
                      double& out) {
  out = read_attr_double(c, obj, where, name);
}

}  // namespace plastivox::h5
