// Output paths: what may be written over.
#pragma once

#include <string>

namespace plastivox {

// Throws InputError naming path when its folder does not exist ("x/y.h5: cannot write: folder
// x does not exist"), or when something that is not a regular file sits there (a
// device such as /dev/null, a pipe, a socket or a folder): every write here renames a
// finished temporary over its path, which would replace that node (as root, a device the
// whole machine uses). A missing path, or a link to a regular file, passes. Every writer calls
// it before it creates anything.
void check_output_path(const std::string& path);

// Removes the temporaries "<path>.tmp.<pid>" that writers killed mid-write left beside path
// (their process is gone), so they cannot pile up. Called where a kill is expected: a video
// being encoded, a results file being checkpointed.
void remove_stale_temporaries(const std::string& path);

}  // namespace plastivox
