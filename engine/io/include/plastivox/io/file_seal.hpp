// The seal: a 512-byte HDF5 user block at the start of every results file and recorded life
// (since 2026-12-05), holding a
// text header with the payload's length and 128-bit hash (internal).
//
// Why: HDF5 parses untrusted metadata, and a damaged file can make a parser do anything.
// The reader checks the seal before HDF5 sees a byte, so a truncated, corrupt or foreign
// file is refused with a precise one-line message. HDF5 ignores user blocks; h5py and
// h5dump open sealed files as usual (a file edited after writing no longer matches its
// seal and is refused).
//
//   plastivox-evolution-results\n  (plastivox-recorded-life\n for a life)
//   seal_version 1\n
//   payload_bytes <N>\n          bytes after the user block
//   payload_hash <32 hex>\n      Hasher over those bytes
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace plastivox::seal {

constexpr uint64_t kUserBlockBytes = 512;

// Which kind of file a seal vouches for: its first line, and what errors call it.
struct Kind {
  const char* magic;  // the header's first line, newline included
  const char* what;   // "evolution results file", "recorded life"
};
inline constexpr Kind kResults{"plastivox-evolution-results\n", "evolution results file"};
inline constexpr Kind kLife{"plastivox-recorded-life\n", "recorded life"};

// Fills the user block at the start of `bytes` (a whole HDF5 file made with that user
// block). `name` names the destination in error messages.
void seal_image(std::string& bytes, const std::string& name, const Kind& kind = kResults);
// The same for the closed HDF5 file `file`, in place.
void write_seal(const std::string& file, const std::string& name);

// True when `file` starts with the seal header of `kind` (whatever follows).
bool has_seal(const std::string& file, const Kind& kind);

// Throws ResultsError when `file` is not a sealed file of `kind` or its payload differs. A
// sealed file of another kind is named as what it is ("life.h5: a recorded life, not an
// evolution results file").
void check_seal(const std::string& file, const Kind& kind = kResults);

// What a file starting with `head` (its first bytes) is when it is HDF5: "an HDF5 file (a
// plastivox recorded life)" for a sealed kind, "an HDF5 file" for HDF5's own signature at
// the start; "" otherwise. For the readers of text formats, which would otherwise call such a
// file "not valid JSON".
std::string describe_hdf5(std::string_view head);

}  // namespace plastivox::seal
