// Writing a file so that nothing half-written ever sits under its final name: the bytes go
// to "<path>.tmp.<pid>", are flushed, and the temporary is renamed over path (atomic on
// POSIX file systems). A full disk or an unwritable folder throws InputError naming path.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "plastivox/base/output_path.hpp"

namespace plastivox {

void write_file_atomic(const std::string& path, std::string_view bytes);

// check_output_path (plastivox/base/output_path.hpp) is called first.

// Largest robot, config or other input file read whole: 256 MiB (docs/robot-format.md).
constexpr uint64_t kMaxInputFileBytes = uint64_t{256} << 20;

// The whole file as bytes. Throws InputError naming path if it cannot be read, is not a
// regular file (a directory, a device such as /dev/zero, a pipe) or holds more than
// max_bytes; the size is checked before anything is read.
std::string read_file_bytes(const std::string& path, uint64_t max_bytes = kMaxInputFileBytes);

}  // namespace plastivox
