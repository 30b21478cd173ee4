#include "engine/mesh/mesh_import.h"

#include <assimp/Importer.hpp>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <unordered_map>

#include "engine/util/error.h"

namespace ps {
namespace {

// Assimp trusts the counts in file headers and allocates before reading (a binary STL declaring
// 2^31 triangles, a PLY list declaring 4e9 entries): every count that assimp would allocate
// from is checked against the bytes actually present before the buffer is handed over.
constexpr long long kMaxImportVertices = 3 * kMaxImportFaces;
// Polygons are ear-clipped by aiProcess_Triangulate in O(n^2): a corrupt face line with a
// million indices would hang it. Real files stay far below this.
constexpr long long kMaxPolygonVertices = 1000;
constexpr long long kMaxOtherList = 100000;
constexpr size_t kMaxHeaderBytes = 64 * 1024;

[[noreturn]] void fail(const std::string& file, const std::string& message, int line = 0,
                       const std::string& field = "") {
  throw InputError(file, line, field, message);
}

std::string fmt_g(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

std::string fmt_vec(double x, double y, double z) {
  return "(" + fmt_g(x) + ", " + fmt_g(y) + ", " + fmt_g(z) + ")";
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext.empty() ? ext : ext.substr(1);
}

std::string read_whole_file(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) fail(path, "cannot read mesh: file does not exist");
  if (!std::filesystem::is_regular_file(status)) fail(path, "cannot read mesh: not a regular file");
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) fail(path, "cannot read mesh: " + ec.message());
  if (size > static_cast<uintmax_t>(kMaxImportFileBytes))
    fail(path, "mesh file is " + std::to_string(size) + " bytes, more than the limit of " +
                   std::to_string(kMaxImportFileBytes));
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, std::string("cannot read mesh: ") + std::strerror(errno));
  std::string data(static_cast<size_t>(size), '\0');
  in.read(data.data(), static_cast<std::streamsize>(data.size()));
  if (static_cast<uintmax_t>(in.gcount()) != size) fail(path, "cannot read mesh: read error");
  return data;
}

// Text formats never contain NUL or most control characters; random or binary data almost
// always does within a few bytes. UTF-8 (bytes >= 0x80) is allowed for names and comments.
// Returns the byte offset of the first offending character, or npos.
size_t first_non_text(std::string_view s) {
  for (size_t i = 0; i < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v') return i;
    if (c == 0x7f) return i;
  }
  return std::string_view::npos;
}

int line_of_offset(std::string_view s, size_t offset) {
  return 1 + static_cast<int>(std::count(s.begin(), s.begin() + std::min(offset, s.size()), '\n'));
}

void require_text(const std::string& file, std::string_view data, const char* what) {
  const size_t bad = first_non_text(data);
  if (bad != std::string_view::npos)
    fail(file,
         std::string("not a valid ") + what + " file: binary byte 0x" +
             [&] {
               char buf[8];
               std::snprintf(buf, sizeof buf, "%02x", static_cast<unsigned char>(data[bad]));
               return std::string(buf);
             }() +
             " at byte offset " + std::to_string(bad),
         line_of_offset(data, bad));
}

// ---- STL -------------------------------------------------------------------------------------

bool starts_with_solid(std::string_view data) {
  size_t i = 0;
  while (i < data.size() && std::isspace(static_cast<unsigned char>(data[i]))) ++i;
  return data.substr(i, 5) == "solid";
}

void precheck_stl(const std::string& file, std::string_view data) {
  const uint64_t size = data.size();
  if (size >= 84) {
    uint32_t n = 0;
    std::memcpy(&n, data.data() + 80, 4);   // little-endian on every platform we build for
    if (84 + 50 * static_cast<uint64_t>(n) == size) {
      if (n == 0) fail(file, "binary STL declares 0 triangles");
      if (n > kMaxImportFaces)
        fail(file, "binary STL declares " + std::to_string(n) + " triangles, more than the limit of " +
                       std::to_string(kMaxImportFaces));
      return;   // a well-formed binary STL: fixed 50-byte records, nothing else to check
    }
    // Assimp decides "binary" with 32-bit arithmetic: a header whose count overflows to the file
    // size would make it allocate billions of triangles. Such a file is corrupt either way.
    if (static_cast<uint32_t>(84u + 50u * n) == static_cast<uint32_t>(size))
      fail(file, "corrupt binary STL: header declares " + std::to_string(n) + " triangles");
    if (!starts_with_solid(data))
      fail(file, "corrupt binary STL: header declares " + std::to_string(n) + " triangles (" +
                     std::to_string(84 + 50 * static_cast<uint64_t>(n)) +
                     " bytes) but the file has " + std::to_string(size) + " bytes");
  } else if (!starts_with_solid(data)) {
    fail(file, "not an STL file: " + std::to_string(size) +
                   " bytes is too short for a binary STL and it does not start with 'solid'");
  }
  require_text(file, data, "ASCII STL");
}

// ---- OBJ -------------------------------------------------------------------------------------

void precheck_obj(const std::string& file, std::string_view data) {
  require_text(file, data, "OBJ");
  // Bound polygon sizes (see kMaxPolygonVertices) and report the line of the offender. A vertex
  // with a coordinate that is not finite in single precision (nan, inf, 1e999; assimp reads
  // floats) is named by its OBJ number and line here: assimp's own numbering of it, one vertex
  // per face corner, is not the file's.
  size_t pos = 0;
  int line = 1;
  long long vertex = 0;
  while (pos < data.size()) {
    size_t end = data.find('\n', pos);
    if (end == std::string_view::npos) end = data.size();
    std::string_view l = data.substr(pos, end - pos);
    size_t i = 0;
    while (i < l.size() && (l[i] == ' ' || l[i] == '\t')) ++i;
    if (i + 1 < l.size() && l[i] == 'v' && (l[i + 1] == ' ' || l[i + 1] == '\t')) {
      ++vertex;
      const std::string coords(l.substr(i + 1));
      const char* c = coords.c_str();
      double xyz[3] = {0.0, 0.0, 0.0};
      bool bad = false;
      for (double& v : xyz) {
        char* next = nullptr;
        v = std::strtod(c, &next);
        if (next == c) break;  // fewer than three numbers: assimp's parser reports it
        bad |= !(std::abs(v) <= std::numeric_limits<float>::max());
        c = next;
      }
      if (bad)
        fail(file, "vertex " + std::to_string(vertex) + " has a non-finite coordinate " +
                       fmt_vec(static_cast<float>(xyz[0]), static_cast<float>(xyz[1]), static_cast<float>(xyz[2])),
             line, "v");
    }
    if (i + 1 < l.size() && (l[i] == 'f' || l[i] == 'l') && (l[i + 1] == ' ' || l[i + 1] == '\t')) {
      long long tokens = 0;
      bool in_token = false;
      for (size_t k = i + 1; k < l.size(); ++k) {
        const bool space = std::isspace(static_cast<unsigned char>(l[k])) != 0;
        if (!space && !in_token) ++tokens;
        in_token = !space;
      }
      if (tokens > kMaxPolygonVertices)
        fail(file, "face with " + std::to_string(tokens) + " vertices (limit " +
                       std::to_string(kMaxPolygonVertices) + ")", line);
    }
    pos = end + 1;
    ++line;
  }
}

// ---- PLY -------------------------------------------------------------------------------------

struct PlyProperty {
  bool is_list = false;
  int count_size = 0;     // bytes of the list count type (lists only)
  bool count_signed = false;
  int value_size = 0;     // bytes of the scalar / list item type
};

struct PlyElement {
  std::string name;
  long long count = 0;
  int header_line = 0;
  std::vector<PlyProperty> props;
};

// Size in bytes of a PLY scalar type, 0 if unknown; *integer tells whether it may be a count.
int ply_type_size(const std::string& t, bool* integer, bool* is_signed) {
  static const struct { const char* name; int size; bool integer; bool is_signed; } kTypes[] = {
      {"char", 1, true, true},     {"int8", 1, true, true},       {"uchar", 1, true, false},
      {"uint8", 1, true, false},   {"short", 2, true, true},      {"int16", 2, true, true},
      {"ushort", 2, true, false},  {"uint16", 2, true, false},    {"int", 4, true, true},
      {"int32", 4, true, true},    {"uint", 4, true, false},      {"uint32", 4, true, false},
      {"float", 4, false, true},   {"float32", 4, false, true},   {"double", 8, false, true},
      {"float64", 8, false, true}};
  for (const auto& k : kTypes)
    if (t == k.name) {
      *integer = k.integer;
      *is_signed = k.is_signed;
      return k.size;
    }
  return 0;
}

std::vector<std::string> split_ws(std::string_view l) {
  std::vector<std::string> out;
  size_t i = 0;
  while (i < l.size()) {
    while (i < l.size() && std::isspace(static_cast<unsigned char>(l[i]))) ++i;
    size_t j = i;
    while (j < l.size() && !std::isspace(static_cast<unsigned char>(l[j]))) ++j;
    if (j > i) out.emplace_back(l.substr(i, j - i));
    i = j;
  }
  return out;
}

bool parse_count(const std::string& s, long long* out) {
  if (s.empty() || s.size() > 12) return false;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), *out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() && *out >= 0;
}

// Allowed list lengths: a face list shorter than 3 makes assimp's Triangulate abort on an
// assertion (Debian builds assimp with asserts on).
long long list_min(const PlyElement& e) { return e.name == "face" ? 3 : 0; }
long long list_max(const PlyElement& e) {
  return (e.name == "face" || e.name == "tristrips") ? kMaxPolygonVertices : kMaxOtherList;
}

void precheck_ply(const std::string& file, std::string_view data) {
  if (data.substr(0, 3) != "ply" || data.size() < 4 || (data[3] != '\n' && data[3] != '\r'))
    fail(file, "not a PLY file: does not start with 'ply'", 1);
  std::string format;
  std::vector<PlyElement> elements;
  size_t pos = 0;
  size_t body = std::string_view::npos;   // offset of the first byte after the header
  int line = 0;
  while (body == std::string_view::npos) {
    size_t end = data.find('\n', pos);
    if (end == std::string_view::npos || end > kMaxHeaderBytes)
      fail(file, "corrupt PLY: no 'end_header' line in the first " + std::to_string(kMaxHeaderBytes) +
                     " bytes");
    ++line;
    const std::string_view l = data.substr(pos, end - pos);
    require_text(file, l, "PLY header of a");
    const auto tok = split_ws(l);
    pos = end + 1;
    if (tok.empty() || tok[0] == "ply" || tok[0] == "comment" || tok[0] == "obj_info") continue;
    if (tok[0] == "end_header") {
      body = pos;
      break;
    }
    if (tok[0] == "format") {
      if (tok.size() < 2 || (tok[1] != "ascii" && tok[1] != "binary_little_endian" &&
                             tok[1] != "binary_big_endian"))
        fail(file, "corrupt PLY header: unknown format", line, "format");
      format = tok[1];
    } else if (tok[0] == "element") {
      PlyElement e;
      if (tok.size() != 3 || !parse_count(tok[2], &e.count))
        fail(file, "corrupt PLY header: bad element declaration", line, "element");
      e.name = tok[1];
      e.header_line = line;
      if (e.count > kMaxImportVertices)
        fail(file, "PLY element '" + e.name + "' declares " + tok[2] + " entries, more than the limit of " +
                       std::to_string(kMaxImportVertices), line, "element");
      if (e.name == "face" && e.count > kMaxImportFaces)
        fail(file, "PLY declares " + tok[2] + " faces, more than the limit of " +
                       std::to_string(kMaxImportFaces), line, "element");
      elements.push_back(std::move(e));
    } else if (tok[0] == "property") {
      if (elements.empty()) fail(file, "corrupt PLY header: property before any element", line, "property");
      PlyProperty p;
      bool integer = false, is_signed = false;
      if (tok.size() == 5 && tok[1] == "list") {
        p.is_list = true;
        p.count_size = ply_type_size(tok[2], &integer, &p.count_signed);
        if (p.count_size == 0 || !integer)
          fail(file, "corrupt PLY header: bad list count type '" + tok[2] + "'", line, "property");
        p.value_size = ply_type_size(tok[3], &integer, &is_signed);
        if (p.value_size == 0) fail(file, "corrupt PLY header: unknown type '" + tok[3] + "'", line, "property");
      } else if (tok.size() == 3) {
        p.value_size = ply_type_size(tok[1], &integer, &is_signed);
        if (p.value_size == 0) fail(file, "corrupt PLY header: unknown type '" + tok[1] + "'", line, "property");
      } else {
        fail(file, "corrupt PLY header: bad property declaration", line, "property");
      }
      elements.back().props.push_back(p);
    } else {
      fail(file, "corrupt PLY header: unknown keyword '" + tok[0] + "'", line);
    }
  }
  if (format.empty()) fail(file, "corrupt PLY header: no 'format' line");
  for (const auto& e : elements)
    if (e.count > 0 && e.props.empty())
      fail(file, "corrupt PLY header: element '" + e.name + "' has no properties", e.header_line, "element");

  // Walk the body once so that every count assimp will allocate from is backed by data.
  const std::string_view b = data.substr(body);
  if (format == "ascii") {
    // Assimp reads one element per line: a value on the next line is not part of the element,
    // and a face read short of its indices aborts Triangulate. So validate line by line.
    require_text(file, b, "ASCII PLY");
    size_t p = 0;
    int body_line = line;
    for (const auto& e : elements) {
      for (long long i = 0; i < e.count; ++i) {
        ++body_line;
        auto bad = [&](const std::string& what) {
          fail(file, "corrupt PLY: element '" + e.name + "' " + std::to_string(i) + " of " +
                         std::to_string(e.count) + ": " + what, body_line);
        };
        if (p >= b.size()) bad("missing (file truncated)");
        size_t end = b.find('\n', p);
        if (end == std::string_view::npos) end = b.size();
        const auto tok = split_ws(b.substr(p, end - p));
        p = end + 1;
        size_t t = 0;
        for (const auto& pr : e.props) {
          long long n = 1;
          if (pr.is_list) {
            if (t >= tok.size()) bad("too few values");
            const std::string& c = tok[t++];
            const auto r = std::from_chars(c.data(), c.data() + c.size(), n);
            if (r.ec != std::errc() || r.ptr != c.data() + c.size() || n < list_min(e) || n > list_max(e))
              bad("bad list length '" + c.substr(0, 20) + "'");
          }
          for (long long k = 0; k < n; ++k) {
            if (t >= tok.size()) bad("too few values");
            std::string_view v = tok[t++];
            if (!v.empty() && v[0] == '+') v.remove_prefix(1);
            double x = 0;
            const auto r = std::from_chars(v.data(), v.data() + v.size(), x);
            if (r.ec != std::errc() || r.ptr != v.data() + v.size())
              bad("non-numeric value '" + std::string(v.substr(0, 20)) + "'");
          }
        }
        if (t != tok.size()) bad("too many values");
      }
    }
  } else {
    const bool big = format == "binary_big_endian";
    uint64_t p = 0;
    for (const auto& e : elements) {
      for (long long i = 0; i < e.count; ++i) {
        for (const auto& pr : e.props) {
          uint64_t bytes = pr.value_size;
          if (pr.is_list) {
            if (p + pr.count_size > b.size()) bytes = ~0ull;   // fall through to the truncation error
            else {
              unsigned char raw[4] = {0, 0, 0, 0};
              for (int k = 0; k < pr.count_size; ++k)
                raw[k] = static_cast<unsigned char>(b[p + (big ? pr.count_size - 1 - k : k)]);
              int64_t n = 0;
              if (pr.count_size == 1) n = pr.count_signed ? int8_t(raw[0]) : raw[0];
              else if (pr.count_size == 2) {
                const uint16_t u = uint16_t(raw[0] | (raw[1] << 8));
                n = pr.count_signed ? int16_t(u) : u;
              } else {
                const uint32_t u = uint32_t(raw[0]) | (uint32_t(raw[1]) << 8) |
                                   (uint32_t(raw[2]) << 16) | (uint32_t(raw[3]) << 24);
                n = pr.count_signed ? int64_t(int32_t(u)) : int64_t(u);
              }
              if (n < list_min(e) || n > list_max(e))
                fail(file, "corrupt PLY: element '" + e.name + "' " + std::to_string(i) +
                               " has a bad list length " + std::to_string(n));
              bytes = pr.count_size + static_cast<uint64_t>(n) * pr.value_size;
            }
          }
          if (bytes > b.size() - p)
            fail(file, "truncated PLY: element '" + e.name + "' " + std::to_string(i) + " of " +
                           std::to_string(e.count) + " ends past the end of the file");
          p += bytes;
        }
      }
    }
  }
}

// ---- scene -> TriMesh ------------------------------------------------------------------------

struct PositionHash {
  size_t operator()(const Vec3& v) const {
    uint64_t h = 1469598103934665603ull;
    for (int k = 0; k < 3; ++k) {
      uint64_t bits;
      const double x = v[k] + 0.0;   // -0 and +0 hash alike
      std::memcpy(&bits, &x, 8);
      h = (h ^ bits) * 1099511628211ull;
      h ^= h >> 29;
    }
    return static_cast<size_t>(h);
  }
};

struct Collector {
  const std::string& file;
  const aiScene* scene;
  TriMesh out;
  std::unordered_map<Vec3, int, PositionHash> index_of;
  std::vector<int> mesh_uses;

  void add_mesh(const aiMesh* m, const aiMatrix4x4& xf) {
    std::vector<int> map(m->mNumVertices, -1);
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices != 3) continue;   // points and lines left over by Triangulate
      std::array<int, 3> tri{};
      for (int k = 0; k < 3; ++k) {
        const unsigned vi = face.mIndices[k];
        if (vi >= m->mNumVertices)
          fail(file, "face " + std::to_string(f) + " uses vertex " + std::to_string(vi) +
                         " but the mesh has only " + std::to_string(m->mNumVertices));
        if (map[vi] < 0) {
          const aiVector3D p = xf * m->mVertices[vi];
          const Vec3 v(p.x, p.y, p.z);
          if (!v.allFinite())
            fail(file, "vertex " + std::to_string(vi) + " (used by face " + std::to_string(f) +
                           ") has a non-finite coordinate " + fmt_vec(p.x, p.y, p.z));
          auto [it, inserted] = index_of.try_emplace(v, static_cast<int>(out.vertices.size()));
          if (inserted) out.vertices.push_back(v);
          map[vi] = it->second;
        }
        tri[k] = map[vi];
      }
      if (static_cast<long long>(out.faces.size()) >= kMaxImportFaces)
        fail(file, "more than " + std::to_string(kMaxImportFaces) + " triangles");
      out.faces.push_back(tri);
    }
  }

  void walk(const aiNode* node, const aiMatrix4x4& parent, int depth) {
    if (!node) return;
    if (depth > 64) fail(file, "scene node hierarchy deeper than 64 levels");
    const aiMatrix4x4 xf = parent * node->mTransformation;
    for (unsigned i = 0; i < node->mNumMeshes; ++i) {
      const unsigned mi = node->mMeshes[i];
      if (mi >= scene->mNumMeshes || !scene->mMeshes[mi]) fail(file, "scene node refers to a missing mesh");
      ++mesh_uses[mi];
      add_mesh(scene->mMeshes[mi], xf);
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c) walk(node->mChildren[c], xf, depth + 1);
  }
};

// Non-finite coordinates are rejected before post-processing: JoinIdenticalVertices sorts by
// position and NaN breaks the strict weak ordering that std::sort relies on.
void check_finite(const std::string& file, const aiScene* scene) {
  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
    const aiMesh* m = scene->mMeshes[mi];
    if (!m || !m->mVertices) continue;
    for (unsigned v = 0; v < m->mNumVertices; ++v) {
      const aiVector3D& p = m->mVertices[v];
      if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) continue;
      std::string where = "vertex " + std::to_string(v);
      for (unsigned f = 0; f < m->mNumFaces; ++f) {
        const aiFace& face = m->mFaces[f];
        if (std::find(face.mIndices, face.mIndices + face.mNumIndices, v) !=
            face.mIndices + face.mNumIndices) {
          where += " (face " + std::to_string(f) + ")";
          break;
        }
      }
      if (scene->mNumMeshes > 1) where += " of mesh " + std::to_string(mi);
      fail(file, where + " has a non-finite coordinate " + fmt_vec(p.x, p.y, p.z));
    }
  }
}

// Assimp's messages quote the unparsable text up to the end of the file: keep the start.
std::string assimp_error(const Assimp::Importer& importer) {
  std::string e = importer.GetErrorString();
  constexpr size_t kMax = 160;
  if (e.size() > kMax) e = e.substr(0, kMax) + "...";
  for (char& c : e)
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  return "cannot import mesh: " + e;
}

Mat3 euler_xyz_deg(const Vec3& deg);

// rotation times scale: what import_mesh and place_like_mesh apply before the translation
Mat3 placement_matrix(const MeshImportOptions& opt) { return euler_xyz_deg(opt.rotate_deg) * opt.scale.asDiagonal(); }

Mat3 euler_xyz_deg(const Vec3& deg) {
  const double k = std::numbers::pi / 180.0;
  // "XYZ applied in that order": rotate about x first, so it is the rightmost factor.
  return (Eigen::AngleAxisd(deg.z() * k, Vec3::UnitZ()) * Eigen::AngleAxisd(deg.y() * k, Vec3::UnitY()) *
          Eigen::AngleAxisd(deg.x() * k, Vec3::UnitX()))
      .toRotationMatrix();
}

}  // namespace

double units_to_metres(const std::string& units, const std::string& file_for_errors) {
  if (units == "mm") return 1e-3;
  if (units == "cm") return 1e-2;
  if (units == "dm") return 1e-1;
  if (units == "m") return 1.0;
  throw InputError(file_for_errors, 0, "units",
                   "unknown length unit '" + units + "' (expected mm, cm, dm or m)");
}

TriMesh import_mesh(const std::string& path, const MeshImportOptions& opt) {
  // Options first: a typo in the scenario should not wait for a large file to load.
  const double unit = units_to_metres(opt.units, path);
  if (!opt.scale.allFinite() || (opt.scale.array() == 0.0).any())
    fail(path, "scale must be finite and non-zero", 0, "scale");
  if (!opt.rotate_deg.allFinite()) fail(path, "rotation must be finite", 0, "rotate_deg");
  if (!opt.translate_m.allFinite()) fail(path, "translation must be finite", 0, "translate_m");

  const std::string ext = lower_extension(path);
  if (ext != "obj" && ext != "stl" && ext != "ply")
    fail(path, "unsupported mesh format '" + (ext.empty() ? std::string("(no extension)") : "." + ext) +
                   "' (expected .obj, .stl or .ply)");
  const std::string data = read_whole_file(path);
  if (data.empty()) fail(path, "empty mesh file");
  if (ext == "stl") precheck_stl(path, data);
  else if (ext == "obj") precheck_obj(path, data);
  else precheck_ply(path, data);

  Assimp::Importer importer;
  // Serve only the buffer already read: OBJ 'mtllib' lines must not make assimp open other files.
  importer.SetIOHandler(new Assimp::MemoryIOSystem(reinterpret_cast<const uint8_t*>(data.data()),
                                                   data.size(), nullptr));
  const std::string name = std::string(AI_MEMORYIO_MAGIC_FILENAME) + "." + ext;
  const aiScene* scene = importer.ReadFile(name, aiProcess_ValidateDataStructure);
  if (!scene) fail(path, assimp_error(importer));
  if (!scene->mRootNode || scene->mNumMeshes == 0 || !scene->mMeshes)
    fail(path, "no triangles in file (no mesh found)");
  check_finite(path, scene);
  scene = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_JoinIdenticalVertices);
  if (!scene) fail(path, assimp_error(importer));

  Collector c{path, scene, {}, {}, std::vector<int>(scene->mNumMeshes, 0)};
  c.walk(scene->mRootNode, aiMatrix4x4(), 0);
  // Meshes no node refers to are still part of the file's geometry.
  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi)
    if (c.mesh_uses[mi] == 0 && scene->mMeshes[mi]) c.add_mesh(scene->mMeshes[mi], aiMatrix4x4());
  TriMesh mesh = std::move(c.out);
  if (mesh.faces.empty()) fail(path, "no triangles in file");

  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (Vec3& v : mesh.vertices) {
    v *= unit;
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const double diag = (hi - lo).norm();   // [m]
  if (!(diag <= 5.0) || !(diag >= 1e-3))
    fail(path, "bounding box diagonal is " + fmt_g(diag) + " m after converting from '" + opt.units +
                   "' (allowed 1 mm to 5 m): wrong units?", 0, "units");

  const Mat3 m = placement_matrix(opt);
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    Vec3& v = mesh.vertices[i];
    v = m * v + opt.translate_m;
    if (!v.allFinite()) fail(path, "vertex " + std::to_string(i) + " is not finite after the transform");
  }
  // A mirroring scale turns an outward surface inside out; keep faces outward.
  if (m.determinant() < 0)
    for (auto& f : mesh.faces) std::swap(f[1], f[2]);
  return mesh;
}

Vec3 place_like_mesh(const Vec3& p_m, const MeshImportOptions& opt) { return placement_matrix(opt) * p_m + opt.translate_m; }

}  // namespace ps
