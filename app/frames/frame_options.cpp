#include "app/frames/frame_options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "engine/util/error.h"

namespace ps::frames {

namespace fs = std::filesystem;

void parse_size(const std::string& s, int& w, int& h) {
  long a = 0, b = 0;
  char x = 0, extra = 0;
  if (std::sscanf(s.c_str(), "%ld%c%ld%c", &a, &x, &b, &extra) != 3 || (x != 'x' && x != 'X'))
    throw InputError("", 0, "--size", "'" + s + "': expected WIDTHxHEIGHT, e.g. 1280x720");
  if (a < 16 || b < 16 || a > kMaxImageSide || b > kMaxImageSide)
    throw InputError("", 0, "--size", "'" + s + "': each side must be 16.." + std::to_string(kMaxImageSide) + " pixels");
  w = static_cast<int>(a);
  h = static_cast<int>(b);
}

render::Antialias parse_antialias_option(const std::string& s) {
  render::Antialias a{};
  if (!render::parse_antialias(s, a))
    throw InputError("", 0, "--aa", "unknown antialiasing '" + s + "' (known: auto, msaa, fxaa, none)");
  return a;
}

const char* us_view_name(us::PlaneKind k) { return k == us::PlaneKind::Transverse ? "us_transverse" : "us_sagittal"; }

std::vector<render::View> parse_views(const std::string& s, std::vector<us::PlaneKind>* us) {
  const std::string known = us ? "3d, anterior, lateral, probe, needle, us_transverse, us_sagittal" : "3d, anterior, lateral, probe, needle";
  std::vector<render::View> out;
  std::vector<us::PlaneKind> planes;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.empty()) continue;
    if (us && (item == "us_transverse" || item == "us_sagittal")) {
      const us::PlaneKind k = item == "us_transverse" ? us::PlaneKind::Transverse : us::PlaneKind::Sagittal;
      if (std::find(planes.begin(), planes.end(), k) != planes.end())
        throw InputError("", 0, "--views", "view '" + item + "' given twice");
      planes.push_back(k);
      continue;
    }
    const auto v = render::parse_view(item);
    if (!v) throw InputError("", 0, "--views", "unknown view '" + item + "' (known: " + known + ")");
    for (render::View u : out)
      if (u == *v) throw InputError("", 0, "--views", "view '" + item + "' given twice");
    out.push_back(*v);
  }
  if (out.empty() && planes.empty()) throw InputError("", 0, "--views", "no view given (known: " + known + ")");
  if (us) *us = planes;
  return out;
}

void prepare_output_dir(const std::string& dir, bool force) {
  if (dir.empty()) throw InputError("", 0, "--out", "empty output folder");
  std::error_code ec;
  const fs::path p(dir);
  if (fs::exists(p, ec)) {
    if (!fs::is_directory(p, ec)) throw InputError(dir, 0, "--out", "exists and is not a folder");
    if (!fs::is_empty(p, ec) && !force)
      throw InputError(dir, 0, "--out", "folder is not empty (use --force to replace a previous replay there)");
  } else {
    fs::create_directories(p, ec);
    if (ec) throw InputError(dir, 0, "--out", "cannot create the folder: " + ec.message());
  }
  // writable?
  const fs::path probe = p / (".prostatesim_probe." + std::to_string(::getpid()));
  {
    std::ofstream f(probe);
    if (!f || !(f << "x") || !(f.flush())) {
      fs::remove(probe, ec);
      throw InputError(dir, 0, "--out", "folder is not writable");
    }
  }
  fs::remove(probe, ec);
  if (force) {
    // only what a replay writes: view folders of frames and the fixed report files
    for (const char* v : {"3d", "anterior", "lateral", "probe", "needle", "us_transverse", "us_sagittal"}) fs::remove_all(p / v, ec);
    for (const char* f : {"events.log", "summary.json", "force_depth.csv", "contact_sheet.png"}) fs::remove(p / f, ec);
  }
}

}  // namespace ps::frames
