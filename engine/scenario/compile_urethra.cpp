// Model::urethra: the prostatic urethra's centre line, read once here so the needle, the metrics,
// the ultrasound and the renderer all use the same line. It lies in urethra.csv beside the mesh
// file of the gland (the `prostate_zones:` component, else the first component whose role is
// prostate), in that file's frame and in millimetres (its header says x_mm); the mesh's scale,
// rotation and translation place it exactly as they place the mesh (place_like_mesh), so a
// scaled or moved prostate keeps its urethra inside.
#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/anatomy/urethra_csv.h"
#include "engine/mesh/mesh_import.h"
#include "engine/scenario/compile_stages.h"

namespace ps {

void compile_urethra(const ScenarioSpec& spec, Model& m) {
  m.urethra.clear();
  const int gland = spec.prostate_zones ? m.find_component(spec.prostate_zones->component) : m.find_role(Role::Prostate);
  if (gland < 0) return;
  const ComponentSpec& c = spec.components[static_cast<size_t>(gland)];
  if (c.shape.kind != ShapeSpec::Mesh || c.shape.mesh.file.empty()) return;
  const std::filesystem::path csv = std::filesystem::path(c.shape.mesh.file).parent_path() / "urethra.csv";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(csv, ec)) return;
  std::ifstream in(csv);
  std::stringstream text;
  text << in.rdbuf();
  MeshImportOptions place;
  place.scale = c.shape.mesh.scale;
  place.rotate_deg = c.shape.mesh.rotate_deg;
  place.translate_m = c.shape.mesh.translate;
  for (const Vec3& p : parse_urethra_csv(text.str(), csv.string())) m.urethra.push_back(place_like_mesh(p, place));
}

}  // namespace ps
