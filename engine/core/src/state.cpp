#include "plastivox/state.hpp"

#include <cstring>
#include <stdexcept>

#include "plastivox/base/hash.hpp"

namespace plastivox {

State make_initial_state(const Model& m) {
  State s;
  PLASTIVOX_INITIAL_VALUES(PLASTIVOX_STATE_FIELDS)
  return s;
}

const std::vector<StateField> kStateFields = PLASTIVOX_ROWS(PLASTIVOX_STATE_FIELDS);

namespace fields {

uint64_t hash(const std::vector<View>& rows) {
  Fnv1a64 f;
  for (const View& row : rows) {
    const uint64_t count = row.bytes.count;
    f.bytes(&count, sizeof count);
    f.bytes(row.bytes.data, row.bytes.count * row.bytes.value_bytes);
  }
  return f.value();
}

namespace {

constexpr char kSnapshotMagic[8] = {'P', 'V', 'X', 'S', 'T', 'A', 'T', '1'};

void put(std::vector<uint8_t>& out, const void* data, size_t bytes) {
  // resize and copy, not insert: GCC 12 sees a false overflow in an inlined insert into the
  // empty vector (-Wstringop-overflow) when this file shares a unity batch.
  if (bytes == 0) return;
  const size_t at = out.size();
  out.resize(at + bytes);
  std::memcpy(out.data() + at, data, bytes);
}
void put_u64(std::vector<uint8_t>& out, uint64_t v) {
  put(out, &v, sizeof v);
}

// Reads a snapshot front to back; every read checks there are bytes left.
struct SnapshotReader {
  const std::vector<uint8_t>& in;
  size_t at = 0;

  const uint8_t* take(size_t bytes, const std::string& what) {
    if (bytes > in.size() - at)
      throw std::invalid_argument("state snapshot: ends inside " + what + " (" +
                                  std::to_string(in.size()) + " bytes; truncated or damaged)");
    const uint8_t* p = in.data() + at;
    at += bytes;
    return p;
  }
  uint64_t u64(const std::string& what) {
    uint64_t v;
    std::memcpy(&v, take(sizeof v, what), sizeof v);
    return v;
  }
};

}  // namespace

std::vector<uint8_t> save(const std::vector<View>& rows, std::string_view text) {
  // Sized once: a snapshot grown by its appends would hold up to twice its bytes (the
  // gradient keeps hundreds of them).
  size_t bytes = sizeof kSnapshotMagic + 8 * (2 + 2 * rows.size()) + text.size();
  for (const View& row : rows) bytes += row.bytes.count * row.bytes.value_bytes;
  std::vector<uint8_t> out;
  out.reserve(bytes);
  put(out, kSnapshotMagic, sizeof kSnapshotMagic);
  put_u64(out, rows.size());
  for (const View& row : rows) {
    const StateFieldBytes& b = row.bytes;
    put_u64(out, b.count);
    put_u64(out, b.value_bytes);
    put(out, b.data, b.count * b.value_bytes);
  }
  put_u64(out, text.size());
  put(out, text.data(), text.size());
  if (out.size() != bytes) throw std::logic_error("state snapshot: sized wrong");
  return out;
}

Read check(const std::vector<View>& rows, const std::vector<uint8_t>& snapshot) {
  SnapshotReader r{snapshot};
  if (std::memcmp(r.take(sizeof kSnapshotMagic, "the header"), kSnapshotMagic,
                  sizeof kSnapshotMagic) != 0)
    throw std::invalid_argument("state snapshot: not a plastivox state (header differs)");
  const uint64_t count = r.u64("the header");
  if (count != rows.size())
    throw std::invalid_argument("state snapshot: holds " + std::to_string(count) +
                                " fields, this build's state " + std::to_string(rows.size()));
  Read read;
  for (const View& row : rows) {
    const std::string name = std::string("field '") + row.name + "'";
    const StateFieldBytes& b = row.bytes;
    const uint64_t values = r.u64(name), value_bytes = r.u64(name);
    if (values != b.count || value_bytes != b.value_bytes)
      throw std::invalid_argument("state snapshot: " + name + " holds " + std::to_string(values) +
                                  " values of " + std::to_string(value_bytes) +
                                  " bytes, this state " + std::to_string(b.count) + " of " +
                                  std::to_string(b.value_bytes) + " (saved from another model?)");
    const uint8_t* p = r.take(b.count * b.value_bytes, name);
    for (size_t k = 0; b.kind == 'b' && k < b.count; ++k)
      if (p[k] > 1) throw std::invalid_argument("state snapshot: " + name + " is not 0 or 1");
    read.from.push_back(p);
  }
  const uint64_t text_bytes = r.u64("the failure text");
  const uint8_t* text = r.take(text_bytes, "the failure text");
  if (r.at != snapshot.size())
    throw std::invalid_argument("state snapshot: " + std::to_string(snapshot.size() - r.at) +
                                " bytes past the end (damaged)");
  read.text.assign(reinterpret_cast<const char*>(text), text_bytes);
  return read;
}

void copy(const std::vector<View>& rows, const Read& read) {
  for (size_t f = 0; f < rows.size(); ++f) {
    const StateFieldBytes& b = rows[f].bytes;
    // The view is read-only for hashing; the struct itself is the caller's to change.
    if (b.count > 0) std::memcpy(const_cast<void*>(b.data), read.from[f], b.count * b.value_bytes);
  }
}

}  // namespace fields

uint64_t state_hash(const State& s) {
  return fields::hash(fields::views(kStateFields, s));
}

std::vector<uint8_t> save_state(const State& s) {
  return fields::save(fields::views(kStateFields, s), s.failure);
}

void restore_state(State& s, const std::vector<uint8_t>& snapshot) {
  // Every check first, so a refused snapshot leaves the state as it was.
  const std::vector<fields::View> rows = fields::views(kStateFields, s);
  const fields::Read read = fields::check(rows, snapshot);
  size_t status_field = 0;
  while (std::strcmp(kStateFields[status_field].name, "status") != 0) ++status_field;
  SimStatus status;
  std::memcpy(&status, read.from[status_field], sizeof status);
  static_assert(sizeof status == sizeof(int));
  if (status != SimStatus::kRunning && status != SimStatus::kFinished &&
      status != SimStatus::kUnstable)
    throw std::invalid_argument("state snapshot: field 'status' is not a status");
  fields::copy(rows, read);
  s.failure = read.text;
}

Vec3 center_of_mass(const std::vector<Vec3>& pos) {
  return center_of_mass(pos, static_cast<int>(pos.size()));
}

Vec3 center_of_mass(const std::vector<Vec3>& pos, int count) {
  Vec3 c = Vec3::Zero();
  for (int i = 0; i < count; ++i) c += pos[i];
  return count == 0 ? c : Vec3(c / static_cast<double>(count));
}

const StateField& state_field(std::string_view name) {
  for (const StateField& f : kStateFields)
    if (name == f.name) return f;
  throw std::invalid_argument("no State field is called " + std::string(name));
}

}  // namespace plastivox
