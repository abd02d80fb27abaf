#include "plastivox/io/file_seal.hpp"

#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>
#include <string_view>
#include <vector>

#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/base/hash.hpp"
#include "plastivox/io/atomic_file.hpp"

namespace plastivox::seal {

// What to do instead of editing a results file in place (the seal refuses such files).
const std::string kCopyOut =
    "; a results file changed after plastivox wrote it (e.g. opened by h5py in 'r+' or 'a' "
    "mode) is refused: read it with h5py.File(path, 'r') and copy what you need into a new "
    "file";
namespace {

constexpr const char* kHdf5Signature = "\x89HDF\r\n\x1a\n";

// Every kind of sealed file plastivox writes.
constexpr const Kind* kKinds[] = {&kResults, &kLife};

bool starts_with(std::string_view bytes, const char* prefix) {
  return bytes.substr(0, std::strlen(prefix)) == prefix;
}

// "a recorded life", "an evolution results file".
std::string with_article(const char* what) {
  return (std::strchr("aeiou", what[0]) ? "an " : "a ") + std::string(what);
}

std::string read_all(const std::string& file, const std::string& name) {
  try {  // a results file may be large: no size limit, but only a regular file
    return read_file_bytes(file, std::numeric_limits<uint64_t>::max());
  } catch (const InputError& e) {
    throw ResultsError(name + ": " + std::string(e.what()).substr(file.size() + 2));
  }
}

Hash128 payload_hash(std::string_view bytes) {
  Hasher h;
  h.bytes(bytes.data() + kUserBlockBytes, bytes.size() - kUserBlockBytes);
  return h.finish();
}

}  // namespace

void seal_image(std::string& bytes, const std::string& name, const Kind& kind) {
  if (bytes.size() < kUserBlockBytes) throw ResultsError(name + ": HDF5 wrote no user block");
  char header[kUserBlockBytes] = {};
  const int n = std::snprintf(header, sizeof header,
                              "%sseal_version 1\npayload_bytes %llu\npayload_hash %s\n", kind.magic,
                              static_cast<unsigned long long>(bytes.size() - kUserBlockBytes),
                              payload_hash(bytes).hex().c_str());
  if (n <= 0 || n >= static_cast<int>(sizeof header)) throw ResultsError(name + ": seal too long");
  std::memcpy(bytes.data(), header, sizeof header);
}

void write_seal(const std::string& file, const std::string& name) {
  std::string bytes = read_all(file, name);
  seal_image(bytes, name);
  std::FILE* f = std::fopen(file.c_str(), "r+b");
  if (!f) throw ResultsError(name + ": cannot reopen " + file + " to seal it");
  const bool ok = std::fwrite(bytes.data(), 1, kUserBlockBytes, f) == kUserBlockBytes;
  const bool closed = std::fclose(f) == 0;
  if (!ok || !closed) throw ResultsError(name + ": cannot write the seal (disk full?)");
}

bool has_seal(const std::string& file, const Kind& kind) {
  const size_t magic_len = std::strlen(kind.magic);
  std::string head(magic_len, '\0');
  std::FILE* f = std::fopen(file.c_str(), "rb");
  if (!f) return false;
  const size_t got = std::fread(head.data(), 1, magic_len, f);
  std::fclose(f);
  return got == magic_len && head == kind.magic;
}

void check_seal(const std::string& file, const Kind& kind) {
  const std::string bytes = read_all(file, file);
  const size_t magic_len = std::strlen(kind.magic);
  const std::string what = kind.what;
  if (bytes.size() < magic_len || std::memcmp(bytes.data(), kind.magic, magic_len) != 0) {
    for (const Kind* other : kKinds)
      if (starts_with(bytes, other->magic))
        throw ResultsError(file + ": " + with_article(other->what) + ", not " +
                           with_article(kind.what));
    if (bytes.size() >= 8 && std::memcmp(bytes.data(), kHdf5Signature, 8) == 0)
      throw ResultsError(file + ": an HDF5 file, but not a plastivox " + what);
    if (bytes.empty()) throw ResultsError(file + ": empty file, not a plastivox " + what);
    throw ResultsError(file + ": not a plastivox " + what +
                       " (not HDF5, or its header is damaged)");
  }
  if (bytes.size() < kUserBlockBytes)
    throw ResultsError(file + ": truncated (" + std::to_string(bytes.size()) +
                       " bytes, header incomplete)");
  const std::string header(bytes.data(), strnlen(bytes.data(), kUserBlockBytes));
  std::istringstream in(header.substr(magic_len));
  std::string k1, k2, k3, hash;
  int version = 0;
  unsigned long long payload = 0;
  in >> k1 >> version >> k2 >> payload >> k3 >> hash;
  if (!in || k1 != "seal_version" || k2 != "payload_bytes" || k3 != "payload_hash")
    throw ResultsError(file + ": damaged header (user block)");
  if (version != 1)
    throw ResultsError(file + ": seal version " + std::to_string(version) + " is not supported");
  const uint64_t have = bytes.size() - kUserBlockBytes;
  if (have < payload)
    throw ResultsError(file + ": truncated (" + std::to_string(have + kUserBlockBytes) + " of " +
                       std::to_string(payload + kUserBlockBytes) + " bytes)");
  if (have > payload)
    throw ResultsError(file + ": has " + std::to_string(have - payload) +
                       " unexpected bytes after its end (modified after writing?)" + kCopyOut);
  if (payload_hash(bytes).hex() != hash)
    throw ResultsError(file + ": corrupt (content does not match its checksum)" + kCopyOut);
}

std::string describe_hdf5(std::string_view head) {
  for (const Kind* k : kKinds)
    if (starts_with(head, k->magic))
      return "an HDF5 file (a plastivox " + std::string(k->what) + ")";
  return starts_with(head, kHdf5Signature) ? "an HDF5 file" : "";
}

}  // namespace plastivox::seal
