#include "app/output_paths.h"

#include <unistd.h>

#include <filesystem>
#include <system_error>

#include "engine/util/error.h"

namespace ps::app {

void prepare_output_file(const std::string& path, const std::string& option) {
  namespace fs = std::filesystem;
  if (path.empty()) return;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(path, 0, option, "is a folder; give a file name");
  fs::path parent = fs::path(path).parent_path();
  if (parent.empty()) parent = ".";
  if (!fs::is_directory(parent, ec)) throw InputError(path, 0, option, "cannot write: the folder " + parent.string() + " does not exist");
  if (::access(parent.c_str(), W_OK) != 0) throw InputError(path, 0, option, "cannot write: the folder " + parent.string() + " is not writable");
}

void prepare_output_dir(const std::string& dir, const std::string& option) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (dir.empty()) throw InputError("", 0, option, "empty output folder");
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) throw InputError(dir, 0, option, "exists and is not a folder");
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir, 0, option, "cannot create the folder: " + ec.message());
  if (::access(dir.c_str(), W_OK) != 0) throw InputError(dir, 0, option, "the folder is not writable");
}

}  // namespace ps::app
