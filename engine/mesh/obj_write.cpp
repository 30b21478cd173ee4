#include "engine/mesh/obj_write.h"

#include <charconv>

#include "engine/util/atomic_file.h"

namespace ps {
namespace {

void append_double(std::string& out, double v) {
  // Shortest representation that parses back to the same double: exact round trip, small file.
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

void append_int(std::string& out, long long v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

}  // namespace

std::string to_obj(const TriMesh& mesh, double scale) {
  std::string out;
  out.reserve(40 * mesh.vertices.size() + 24 * mesh.faces.size() + 64);
  out += "# ProstateSim surface: ";
  append_int(out, static_cast<long long>(mesh.vertices.size()));
  out += " vertices, ";
  append_int(out, static_cast<long long>(mesh.faces.size()));
  out += " triangles\n";
  for (const Vec3& v : mesh.vertices) {
    out += "v ";
    append_double(out, v.x() * scale);
    out += ' ';
    append_double(out, v.y() * scale);
    out += ' ';
    append_double(out, v.z() * scale);
    out += '\n';
  }
  for (const auto& f : mesh.faces) {
    out += "f ";
    append_int(out, f[0] + 1LL);
    out += ' ';
    append_int(out, f[1] + 1LL);
    out += ' ';
    append_int(out, f[2] + 1LL);
    out += '\n';
  }
  return out;
}

void write_obj(const std::string& path, const TriMesh& mesh, double scale) {
  write_file_atomic(path, to_obj(mesh, scale));
}

}  // namespace ps
