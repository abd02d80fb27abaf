#include "plastivox/io/h5_util.hpp"

#include <sys/stat.h>

#include <cstring>
#include <iterator>
#include <limits>
#include <type_traits>

namespace plastivox::h5 {
namespace {

// Each element type's HDF5 types: in the file (little-endian, whatever the machine) and in
// memory, and its class.
struct ElementType {
  hid_t file, mem;
  H5T_class_t cls;
};
template <class T>
ElementType type_of() {
  if constexpr (std::is_same_v<T, uint8_t>)
    return {H5T_STD_U8LE, H5T_NATIVE_UINT8, H5T_INTEGER};
  else if constexpr (std::is_same_v<T, int32_t>)
    return {H5T_STD_I32LE, H5T_NATIVE_INT32, H5T_INTEGER};
  else if constexpr (std::is_same_v<T, int64_t>)
    return {H5T_STD_I64LE, H5T_NATIVE_INT64, H5T_INTEGER};
  else if constexpr (std::is_same_v<T, uint64_t>)
    return {H5T_STD_U64LE, H5T_NATIVE_UINT64, H5T_INTEGER};
  else {
    static_assert(std::is_same_v<T, double>, "an element type with no HDF5 type here");
    return {H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, H5T_FLOAT};
  }
}

// Path of an object for messages ("/generations/fitness").
std::string path_of(hid_t loc, const std::string& name) {
  char buf[512] = "";
  const ssize_t n = H5Iget_name(loc, buf, sizeof buf);
  std::string base = n > 0 ? std::string(buf) : std::string("?");
  if (name.empty()) return base;
  if (base.empty() || base.back() != '/') base += '/';
  return base + name;
}

Handle check(const Ctx& c, hid_t id, Handle::Kind kind, const std::string& object,
             const std::string& what) {
  if (id < 0) c.fail(object, what);
  return Handle(id, kind);
}

void check(const Ctx& c, herr_t rc, const std::string& object, const std::string& what) {
  if (rc < 0) c.fail(object, what);
}

std::string type_name(H5T_class_t cls) {
  switch (cls) {
    case H5T_INTEGER:
      return "integer";
    case H5T_FLOAT:
      return "floating-point";
    case H5T_STRING:
      return "string";
    default:
      return "other";
  }
}

// Opens a dataset, checks its element class and rank/extents; returns its dims.
Handle open_checked(const Ctx& c, hid_t loc, const std::string& name, H5T_class_t cls,
                    size_t elem_size, std::vector<hsize_t>& dims) {
  const std::string obj = path_of(loc, name);
  if (!has_link(loc, name)) c.fail(obj, "missing");
  Handle d = check(c, H5Dopen2(loc, name.c_str(), H5P_DEFAULT), Handle::Kind::kDataset, obj,
                   "cannot open dataset (not a dataset, or corrupt)");
  Handle t = check(c, H5Dget_type(d.id()), Handle::Kind::kDatatype, obj, "cannot read type");
  const H5T_class_t got = H5Tget_class(t.id());
  if (got != cls) c.fail(obj, "expected " + type_name(cls) + " data, found " + type_name(got));
  Handle s = check(c, H5Dget_space(d.id()), Handle::Kind::kDataspace, obj, "cannot read shape");
  const int rank = H5Sget_simple_extent_ndims(s.id());
  if (rank != static_cast<int>(dims.size()))
    c.fail(obj, "expected rank " + std::to_string(dims.size()) + ", found " + std::to_string(rank));
  std::vector<hsize_t> got_dims(dims.size());
  if (rank > 0)
    check(c, H5Sget_simple_extent_dims(s.id(), got_dims.data(), nullptr), obj, "bad shape");
  uint64_t count = 1;
  for (size_t i = 0; i < dims.size(); ++i) {
    if (dims[i] != kAnyExtent && dims[i] != got_dims[i])
      c.fail(obj, "expected extent " + std::to_string(dims[i]) + " in dimension " +
                      std::to_string(i) + ", found " + std::to_string(got_dims[i]));
    count *= got_dims[i];
  }
  // A corrupt header could claim any size: no dataset of ours is larger than the file.
  if (c.file_size > 0 && count > c.file_size / (elem_size ? elem_size : 1) + 1)
    c.fail(obj, "claims more data than the file holds (corrupt)");
  dims = got_dims;
  return d;
}

}  // namespace

void quiet_hdf5() {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

Handle& Handle::operator=(Handle&& o) noexcept {
  if (this != &o) {
    reset();
    id_ = o.id_;
    kind_ = o.kind_;
    o.id_ = -1;
  }
  return *this;
}

herr_t Handle::close() {
  // Each kind's close call, in Kind's order.
  static herr_t (*const kClose[])(hid_t) = {H5Fclose, H5Gclose, H5Dclose, H5Sclose,
                                            H5Tclose, H5Aclose, H5Pclose};
  static_assert(std::size(kClose) == static_cast<size_t>(Kind::kPlist) + 1);
  if (id_ < 0) return 0;
  const herr_t rc = kClose[static_cast<int>(kind_)](id_);
  id_ = -1;
  return rc;
}

void Handle::reset() {
  close();
}

void Ctx::fail(const std::string& object, const std::string& what) const {
  throw ResultsError(file + ": " + object + ": " + what);
}

Ctx read_context(const std::string& path) {
  quiet_hdf5();
  struct stat sb {};
  if (::stat(path.c_str(), &sb) != 0) throw ResultsError(path + ": no such file");
  if (!S_ISREG(sb.st_mode)) throw ResultsError(path + ": not a regular file");
  return Ctx{path, static_cast<uint64_t>(sb.st_size)};
}

MemoryFile::MemoryFile(const Ctx& c, hsize_t user_block) : c_(c), user_block_(user_block) {
  quiet_hdf5();
  Handle fcpl = check(c, H5Pcreate(H5P_FILE_CREATE), Handle::Kind::kPlist, "(file)",
                      "cannot make a file-creation property list");
  if (user_block > 0)
    check(c, H5Pset_userblock(fcpl.id(), user_block), "(file)", "cannot set up the user block");
  Handle fapl = check(c, H5Pcreate(H5P_FILE_ACCESS), Handle::Kind::kPlist, "(file)",
                      "cannot make a file-access property list");
  check(c, H5Pset_fapl_core(fapl.id(), size_t{1} << 20, 0), "(file)",
        "cannot select the in-memory driver");
  file_ = check(c, H5Fcreate(c.file.c_str(), H5F_ACC_TRUNC, fcpl.id(), fapl.id()),
                Handle::Kind::kFile, "(file)", "cannot create the file in memory");
}

std::string MemoryFile::image() {
  check(c_, H5Fflush(file_.id(), H5F_SCOPE_GLOBAL), "(file)", "cannot flush (out of memory?)");
  const ssize_t n = H5Fget_file_image(file_.id(), nullptr, 0);
  if (n < 0) c_.fail("(file)", "cannot read back the file image");
  std::string bytes(user_block_ + static_cast<size_t>(n), '\0');
  if (H5Fget_file_image(file_.id(), bytes.data() + user_block_, static_cast<size_t>(n)) != n)
    c_.fail("(file)", "cannot read back the file image");
  check(c_, file_.close(), "(file)", "cannot close the in-memory file");
  return bytes;
}

bool has_link(hid_t loc, const std::string& name) {
  // Check each component, so a missing parent group is not an error inside HDF5.
  size_t start = 0;
  while (start <= name.size()) {
    const size_t slash = name.find('/', start);
    const std::string prefix = name.substr(0, slash);
    if (H5Lexists(loc, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  return true;
}

Handle create_group(const Ctx& c, hid_t loc, const std::string& name) {
  return check(c, H5Gcreate2(loc, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
               Handle::Kind::kGroup, path_of(loc, name), "cannot create group");
}

Handle open_group(const Ctx& c, hid_t loc, const std::string& name) {
  const std::string obj = path_of(loc, name);
  if (name != "/" && !has_link(loc, name)) c.fail(obj, "missing");
  Handle g = check(c, H5Gopen2(loc, name.c_str(), H5P_DEFAULT), Handle::Kind::kGroup, obj,
                   "cannot open group (not a group, or corrupt)");
  return g;
}

template <class T>
void write(const Ctx& c, hid_t loc, const std::string& name, const std::vector<T>& data,
           const std::vector<hsize_t>& dims) {
  const std::string obj = path_of(loc, name);
  hsize_t count = 1;
  for (hsize_t d : dims) count *= d;
  if (count != data.size()) c.fail(obj, "internal error: shape does not match the data");
  Handle s = check(c, H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                   Handle::Kind::kDataspace, obj, "cannot create dataspace");
  Handle d = check(c,
                   H5Dcreate2(loc, name.c_str(), type_of<T>().file, s.id(), H5P_DEFAULT,
                              H5P_DEFAULT, H5P_DEFAULT),
                   Handle::Kind::kDataset, obj, "cannot create dataset");
  if (count > 0)
    check(c, H5Dwrite(d.id(), type_of<T>().mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), obj,
          "write failed (disk full?)");
  check(c, d.close(), obj, "close failed");
}

template <class T>
std::vector<T> read(const Ctx& c, hid_t loc, const std::string& name, std::vector<hsize_t>& dims) {
  Handle d = open_checked(c, loc, name, type_of<T>().cls, sizeof(T), dims);
  hsize_t count = 1;
  for (hsize_t x : dims) count *= x;
  std::vector<T> out(count);
  if (count > 0)
    check(c, H5Dread(d.id(), type_of<T>().mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()),
          path_of(loc, name), "read failed (corrupt or truncated file)");
  return out;
}

#define PLASTIVOX_H5_INSTANTIATE(T)                                                    \
  template void write<T>(const Ctx&, hid_t, const std::string&, const std::vector<T>&, \
                         const std::vector<hsize_t>&);                                 \
  template std::vector<T> read<T>(const Ctx&, hid_t, const std::string&, std::vector<hsize_t>&);
PLASTIVOX_H5_INSTANTIATE(uint8_t)
PLASTIVOX_H5_INSTANTIATE(int32_t)
PLASTIVOX_H5_INSTANTIATE(int64_t)
PLASTIVOX_H5_INSTANTIATE(uint64_t)
PLASTIVOX_H5_INSTANTIATE(double)
#undef PLASTIVOX_H5_INSTANTIATE

namespace {

// A fixed-length, NUL-terminated string type of `size` bytes in character set `cset`.
Handle string_type(const Ctx& c, size_t size, const std::string& obj,
                   H5T_cset_t cset = H5T_CSET_ASCII) {
  Handle t = check(c, H5Tcopy(H5T_C_S1), Handle::Kind::kDatatype, obj, "cannot make string type");
  check(c, H5Tset_size(t.id(), size), obj, "cannot size string type");
  check(c, H5Tset_strpad(t.id(), H5T_STR_NULLTERM), obj, "cannot set string padding");
  check(c, H5Tset_cset(t.id(), cset), obj, "cannot set the character set");
  return t;
}

// The type every string is written with: variable-length UTF-8, which h5py returns as str
// (fixed-length strings come back as bytes).
Handle utf8_type(const Ctx& c, const std::string& obj) {
  return string_type(c, H5T_VARIABLE, obj, H5T_CSET_UTF8);
}

// Frees what HDF5 allocated reading variable-length strings into `buf` (type `mem`).
void reclaim(hid_t mem, hid_t space, void* buf) {
#if H5_VERSION_GE(1, 12, 0)
  H5Treclaim(mem, space, H5P_DEFAULT, buf);
#else
  H5Dvlen_reclaim(mem, space, H5P_DEFAULT, buf);
#endif
}

// Strings read from an object of file type `ft` holding `n` values, through `read` (a
// dataset or attribute read into a buffer of memory type `mt`): variable-length (what this
// build writes) or fixed-length (files written before it), in the file's own character set
// (HDF5 does not convert between ASCII and UTF-8).
template <class Read>
std::vector<std::string> read_string_values(const Ctx& c, hid_t ft, hsize_t n,
                                            const std::string& obj, const Read& read) {
  const H5T_cset_t cset = H5Tget_cset(ft);
  if (cset != H5T_CSET_ASCII && cset != H5T_CSET_UTF8) c.fail(obj, "unknown character set");
  std::vector<std::string> out(n);
  if (H5Tis_variable_str(ft) > 0) {
    Handle mt = string_type(c, H5T_VARIABLE, obj, cset);
    std::vector<char*> ptrs(n, nullptr);
    if (n == 0) return out;
    check(c, read(mt.id(), static_cast<void*>(ptrs.data())), obj,
          "read failed (corrupt or truncated file)");
    for (hsize_t i = 0; i < n; ++i) out[i] = ptrs[i] ? std::string(ptrs[i]) : std::string();
    Handle sp = check(c, H5Screate_simple(1, &n, nullptr), Handle::Kind::kDataspace, obj,
                      "cannot create dataspace");
    reclaim(mt.id(), sp.id(), ptrs.data());
    return out;
  }
  const size_t width = H5Tget_size(ft);
  if (width == 0 || width > (1u << 24)) c.fail(obj, "implausible string width");
  if (c.file_size > 0 && n * width > c.file_size)
    c.fail(obj, "claims more data than the file holds");
  Handle mt = string_type(c, width, obj, cset);
  std::vector<char> buf(width * n + 1, '\0');
  if (n > 0)
    check(c, read(mt.id(), static_cast<void*>(buf.data())), obj,
          "read failed (corrupt or truncated file)");
  for (hsize_t i = 0; i < n; ++i)
    out[i] = std::string(&buf[i * width], strnlen(&buf[i * width], width));
  return out;
}

}  // namespace

void write_strings(const Ctx& c, hid_t loc, const std::string& name,
                   const std::vector<std::string>& s) {
  const std::string obj = path_of(loc, name);
  std::vector<const char*> ptrs;
  ptrs.reserve(s.size());
  for (const std::string& x : s) ptrs.push_back(x.c_str());
  Handle t = utf8_type(c, obj);
  const hsize_t n = s.size();
  Handle sp = check(c, H5Screate_simple(1, &n, nullptr), Handle::Kind::kDataspace, obj,
                    "cannot create dataspace");
  Handle d = check(
      c, H5Dcreate2(loc, name.c_str(), t.id(), sp.id(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
      Handle::Kind::kDataset, obj, "cannot create dataset");
  if (n > 0)
    check(c, H5Dwrite(d.id(), t.id(), H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()), obj,
          "write failed (disk full?)");
}

std::vector<std::string> read_strings(const Ctx& c, hid_t loc, const std::string& name, hsize_t n) {
  const std::string obj = path_of(loc, name);
  std::vector<hsize_t> dims = {n};
  Handle d = open_checked(c, loc, name, H5T_STRING, 1, dims);
  Handle ft = check(c, H5Dget_type(d.id()), Handle::Kind::kDatatype, obj, "cannot read type");
  return read_string_values(c, ft.id(), n, obj, [&](hid_t mt, void* buf) {
    return H5Dread(d.id(), mt, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
  });
}

namespace {

Handle scalar_space(const Ctx& c, const std::string& obj) {
  return check(c, H5Screate(H5S_SCALAR), Handle::Kind::kDataspace, obj, "cannot create dataspace");
}

void write_attr_raw(const Ctx& c, hid_t obj_id, const std::string& name, hid_t file_type,
                    hid_t mem_type, const void* value) {
  const std::string obj = path_of(obj_id, "") + "@" + name;
  if (H5Aexists(obj_id, name.c_str()) > 0)
    check(c, H5Adelete(obj_id, name.c_str()), obj, "cannot replace");
  Handle s = scalar_space(c, obj);
  Handle a = check(c, H5Acreate2(obj_id, name.c_str(), file_type, s.id(), H5P_DEFAULT, H5P_DEFAULT),
                   Handle::Kind::kAttribute, obj, "cannot create attribute");
  check(c, H5Awrite(a.id(), mem_type, value), obj, "cannot write attribute");
}

Handle open_attr(const Ctx& c, hid_t obj_id, const std::string& where, const std::string& name,
                 H5T_class_t cls) {
  const std::string obj = where + "@" + name;
  if (H5Aexists(obj_id, name.c_str()) <= 0) c.fail(obj, "missing attribute");
  Handle a = check(c, H5Aopen(obj_id, name.c_str(), H5P_DEFAULT), Handle::Kind::kAttribute, obj,
                   "cannot open attribute");
  Handle t = check(c, H5Aget_type(a.id()), Handle::Kind::kDatatype, obj, "cannot read type");
  if (H5Tget_class(t.id()) != cls)
    c.fail(obj, "expected " + type_name(cls) + ", found " + type_name(H5Tget_class(t.id())));
  Handle s = check(c, H5Aget_space(a.id()), Handle::Kind::kDataspace, obj, "cannot read shape");
  if (H5Sget_simple_extent_npoints(s.id()) != 1) c.fail(obj, "expected a single value");
  return a;
}

}  // namespace

void write_attr(const Ctx& c, hid_t obj, const std::string& name, const std::string& value) {
  Handle t = utf8_type(c, name);
  const char* text = value.c_str();
  write_attr_raw(c, obj, name, t.id(), t.id(), static_cast<const void*>(&text));
}

void write_units(const Ctx& c, hid_t loc, const std::string& dataset, const std::string& units) {
  Handle d = check(c, H5Dopen2(loc, dataset.c_str(), H5P_DEFAULT), Handle::Kind::kDataset,
                   path_of(loc, dataset), "cannot open dataset");
  write_attr(c, d.id(), "units", units);
}

void write_attr(const Ctx& c, hid_t obj, const std::string& name, int64_t value) {
  write_attr_raw(c, obj, name, H5T_STD_I64LE, H5T_NATIVE_INT64, &value);
}

void write_attr_u64(const Ctx& c, hid_t obj, const std::string& name, uint64_t value) {
  write_attr_raw(c, obj, name, H5T_STD_U64LE, H5T_NATIVE_UINT64, &value);
}

void write_attr(const Ctx& c, hid_t obj, const std::string& name, double value) {
  write_attr_raw(c, obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value);
}

bool has_attr(hid_t obj, const std::string& name) {
  return H5Aexists(obj, name.c_str()) > 0;
}

std::string read_attr_string(const Ctx& c, hid_t obj, const std::string& where,
                             const std::string& name) {
  Handle a = open_attr(c, obj, where, name, H5T_STRING);
  const std::string o = where + "@" + name;
  Handle ft = check(c, H5Aget_type(a.id()), Handle::Kind::kDatatype, o, "cannot read type");
  return read_string_values(c, ft.id(), 1, o,
                            [&](hid_t mt, void* buf) { return H5Aread(a.id(), mt, buf); })[0];
}

int64_t read_attr_int(const Ctx& c, hid_t obj, const std::string& where, const std::string& name) {
  Handle a = open_attr(c, obj, where, name, H5T_INTEGER);
  int64_t v = 0;
  check(c, H5Aread(a.id(), H5T_NATIVE_INT64, &v), where + "@" + name, "cannot read attribute");
  return v;
}

uint64_t read_attr_u64(const Ctx& c, hid_t obj, const std::string& where, const std::string& name) {
  Handle a = open_attr(c, obj, where, name, H5T_INTEGER);
  uint64_t v = 0;
  check(c, H5Aread(a.id(), H5T_NATIVE_UINT64, &v), where + "@" + name, "cannot read attribute");
  return v;
}

double read_attr_double(const Ctx& c, hid_t obj, const std::string& where,
                        const std::string& name) {
  Handle a = open_attr(c, obj, where, name, H5T_FLOAT);
  double v = 0;
  check(c, H5Aread(a.id(), H5T_NATIVE_DOUBLE, &v), where + "@" + name, "cannot read attribute");
  return v;
}

}  // namespace plastivox::h5
