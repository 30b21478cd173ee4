// Write a file atomically: content goes to "<path>.tmp.<pid>", is flushed, then renamed over
// <path>. A crash mid-write leaves the previous file (or none), never a half-written one.
#pragma once
#include <string>
#include <string_view>

namespace ps {

// Throws InputError naming the path on failure (a folder that is missing or read-only, a full
// disk: the path or the machine, not a bug); the temp file is removed.
void write_file_atomic(const std::string& path, std::string_view content);

}  // namespace ps
