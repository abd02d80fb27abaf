// A read that may crash, run first in a child process: for files that nothing vouches for.
//
// Why: HDF5 1.10 trusts a file's metadata. A damaged recorded life without a seal (written
// before seals came in on 2026-12-05, or with its seal cut off) made it fault inside a string
// attribute's read (H5HG_read <- H5Aread), taking `render`, `view` and Python down with
// SIGSEGV. Checking every structure before HDF5 reads it would mean writing a second HDF5
// parser; reading in a forked child turns any crash into an error, at the cost of reading an
// unsealed file twice (in the child, then here once the child succeeded: the same bytes
// through the same code). Sealed files need none of this: their seal is checked first.
#pragma once

#include <functional>
#include <string>

namespace plastivox {

struct ChildRead {
  enum class Outcome {
    kOk,       // `read` returned
    kError,    // `read` threw: `message` is the exception's text
    kCrashed,  // the child died: `message` says how ("signal 11 (Segmentation fault)"; a
               // read past the CPU limit is signal 24, "CPU time limit exceeded")
    kNoChild,  // no child could be started: `message` says why (fork or pipe failed)
  };
  Outcome outcome = Outcome::kOk;
  std::string message;
};

// Runs `read` in a forked child process (no core file, its stderr discarded, at most
// `cpu_seconds` of CPU time: a damaged global heap made HDF5 loop for ever) and waits for it.
// The child only reports; whatever `read` produced stays there. POSIX only.
ChildRead run_in_child(const std::function<void()>& read, int cpu_seconds);

}  // namespace plastivox
