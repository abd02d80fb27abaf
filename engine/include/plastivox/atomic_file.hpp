// Writing a file so that nothing half-written ever sits under its final name: the bytes go
// to "<path>.tmp.<pid>", are flushed, and the temporary is renamed over path (atomic on
// POSIX file systems). A full disk or an unwritable folder throws InputError naming path.
#pragma once

#include <string>
#include <string_view>

namespace plastivox {

void write_file_atomic(const std::string& path, std::string_view bytes);

// The whole file as bytes; throws InputError naming path if it cannot be read.
std::string read_file_bytes(const std::string& path);

}  // namespace plastivox
