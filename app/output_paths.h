// Output paths the user names on the command line (--json, --csv, --out, --report), checked before
// any work starts: a run of minutes must not end in a failed write, and a path that cannot be
// written is bad input (exit 2 naming the option), not an internal error.
#pragma once
#include <string>

namespace ps::app {

// A file to be written at the end (atomically, engine/util/atomic_file.h): its folder must exist
// and be writable, and the path must not be a folder. InputError naming the option otherwise.
// An empty path (the option not given) passes.
void prepare_output_file(const std::string& path, const std::string& option);

// An output folder: created if missing, and writable. InputError naming the option otherwise.
void prepare_output_dir(const std::string& dir, const std::string& option);

}  // namespace ps::app
