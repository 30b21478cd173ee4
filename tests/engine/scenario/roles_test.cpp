// `role:` on components and tags: parsed, refused with file:line:field when unknown, resolved once
// at compile into Component::role / Model::tag_roles (a name only as the default of the role), and
// the urethra centre line read once at compile, placed like the gland's mesh.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "engine/scenario/model_hash.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/ultrasound/anatomy.h"
#include "engine/util/error.h"

namespace ps {
namespace {

namespace fs = std::filesystem;

// Two linked boxes; `a_extra` / `b_extra` are keys added to each component (4-space indent).
std::string two_boxes(const std::string& a_extra, const std::string& b_extra, const std::string& tail = "") {
  return "name: roles\n"
         "gravity_m_s2: [0, 0, 0]\n"
         "materials:\n"
         "  soft: {young_kpa: 3, density_kg_m3: 1000}\n"
         "components:\n"
         "  - name: gland_left_thing\n"        // line 6
         "    material: soft\n"
         "    spacing_mm: 5\n"
         "    box: {min_mm: [0, 0, 0], max_mm: [20, 20, 20]}\n" +
         a_extra +
         "  - name: tissue\n"
         "    material: soft\n"
         "    spacing_mm: 5\n"
         "    box: {min_mm: [0, 0, 25], max_mm: [20, 20, 45]}\n" +
         b_extra +
         "links:\n"
         "  - {a: gland_left_thing, b: tissue, distance_mm: 7}\n" +
         tail;
}

std::shared_ptr<const Model> compile(const std::string& yaml) { return compile_scenario(parse_scenario_text(yaml, "t.yaml")); }

TEST(Roles, AGivenRoleWinsOverTheNameAndTheNameIsTheDefault) {
  const auto by_name = compile(two_boxes("", ""));
  EXPECT_EQ(by_name->components[0].role, Role::Prostate);  // "gland" in the name
  EXPECT_EQ(by_name->components[1].role, Role::Other);
  EXPECT_EQ(by_name->find_role(Role::Prostate), 0);
  EXPECT_EQ(by_name->find_role(Role::Bladder), -1);

  const auto given = compile(two_boxes("    role: bladder\n", "    role: prostate\n"));
  EXPECT_EQ(given->components[0].role, Role::Bladder);
  EXPECT_EQ(given->components[1].role, Role::Prostate);
  EXPECT_EQ(given->find_role(Role::Bladder), 0);
  EXPECT_EQ(given->find_role(Role::Prostate), 1);
  EXPECT_EQ(given->find_organ("", Role::Prostate), 1);
  EXPECT_EQ(given->find_organ("gland_left_thing", Role::Prostate), 0);
  // a role other than the name's default is a different compiled scene; the default itself is not
  EXPECT_NE(model_hash(*given), model_hash(*by_name));
  EXPECT_EQ(model_hash(*compile(two_boxes("    role: prostate\n", ""))), model_hash(*by_name));
  // what the ultrasound makes of them follows the role
  const us::UltrasoundAnatomy a = us::build_anatomy(*given);
  ASSERT_EQ(a.components.size(), 2u);
  EXPECT_EQ(a.components[0].tissue, us::Tissue::Bladder);
  EXPECT_EQ(a.components[1].tissue, us::Tissue::Prostate);
  EXPECT_EQ(a.prostate, 1);
}

TEST(Roles, AnUnknownRoleIsRefusedWithFileLineAndField) {
  try {
    parse_scenario_text(two_boxes("", "    role: kidney\n"), "t.yaml");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "t.yaml");
    EXPECT_EQ(e.line(), 14);
    EXPECT_EQ(e.field(), "components[1].role");
    EXPECT_NE(e.message().find("kidney"), std::string::npos);
    EXPECT_NE(e.message().find("bladder"), std::string::npos);  // lists the known roles
  }
  try {
    parse_scenario_text(two_boxes("", "", "tags:\n  - {name: spot, role: Lesion, component: tissue, region: {sphere: {center_mm: [10, 10, 35], radius_mm: 6}}}\n"),
                        "t.yaml");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 17);
    EXPECT_EQ(e.field(), "tags[0].role");
  }
}

TEST(Roles, TagsCarryRolesAndLesionTagsByName) {
  const std::string tags =
      "tags:\n"
      "  - {name: spot, role: lesion, component: tissue, region: {sphere: {center_mm: [10, 10, 35], radius_mm: 6}}}\n"
      "  - {name: lesion_b, component: tissue, region: {sphere: {center_mm: [10, 10, 26], radius_mm: 5}}}\n"
      "  - {name: tumour_c, role: other, component: gland_left_thing, region: {sphere: {center_mm: [10, 10, 10], radius_mm: 6}}}\n";
  const auto m = compile(two_boxes("", "    role: prostate\n", tags));
  ASSERT_EQ(m->tag_roles.size(), m->tag_names.size());
  EXPECT_EQ(m->tag_role(m->find_tag("spot")), Role::Lesion);
  EXPECT_EQ(m->tag_role(m->find_tag("lesion_b")), Role::Lesion);
  EXPECT_EQ(m->tag_role(m->find_tag("tumour_c")), Role::Other);
  // the ultrasound draws the lesions the roles name: "spot" yes, "tumour_c" no
  const us::UltrasoundAnatomy a = us::build_anatomy(*m);
  std::vector<std::string> names;
  for (const auto& l : a.lesions) names.push_back(l.name);
  EXPECT_EQ(names, (std::vector<std::string>{"spot", "lesion_b"}));
  const int spot = m->find_tag("spot");
  for (int p = 0; p < m->particle_count(); ++p)
    if (m->particle_tags[p] >> spot & 1u) {
      EXPECT_EQ(us::prostate_particle_echo(*m, p), 0.3f);
      break;
    }
}

// A 20 mm cube centred on the origin (OBJ, mm) with a urethra.csv beside it.
fs::path cube_with_urethra(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("ps_roles_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  std::ofstream obj(d / "organ.obj");
  for (int k = 0; k < 8; ++k) obj << "v " << (k & 1 ? 10 : -10) << " " << (k & 2 ? 10 : -10) << " " << (k & 4 ? 10 : -10) << "\n";
  // outward faces (1-based): -x, +x, -y, +y, -z, +z
  obj << "f 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\nf 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\nf 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\n";
  std::ofstream csv(d / "urethra.csv");
  csv << "# test line\nx_mm,y_mm,z_mm\n2,0,-5\n2,0,0\n2,0,5\n";
  return d;
}

std::string mesh_scene(const fs::path& d, const std::string& name, const std::string& mesh_extra, const std::string& role = "") {
  return "name: urethra\n"
         "gravity_m_s2: [0, 0, 0]\n"
         "materials:\n"
         "  soft: {young_kpa: 3, density_kg_m3: 1000}\n"
         "components:\n"
         "  - name: " + name + "\n" + role +
         "    material: soft\n"
         "    spacing_mm: 6\n"
         "    mesh: {file: " + (d / "organ.obj").string() + ", units: mm" + mesh_extra + "}\n";
}

TEST(Roles, TheUrethraIsPlacedLikeTheGlandsMesh) {
  const fs::path d = cube_with_urethra("placed");
  // untransformed: the file's points in metres
  const auto plain = compile(mesh_scene(d, "prostate", ""));
  ASSERT_EQ(plain->urethra.size(), 3u);
  EXPECT_EQ(plain->urethra[0], Vec3(2e-3, 0, -5e-3));
  // scaled by 2, turned 90 degrees about z, moved 10 mm along x: (2, 0, -5) -> (4, 0, -10)
  // -> (0, 4, -10) -> (10, 4, -10) mm, as the mesh's own vertices
  const auto moved = compile(mesh_scene(d, "prostate", ", scale: 2, rotate_deg: [0, 0, 90], translate_mm: [10, 0, 0]"));
  ASSERT_EQ(moved->urethra.size(), 3u);
  EXPECT_LT((moved->urethra[0] - Vec3(10e-3, 4e-3, -10e-3)).norm(), 1e-12);
  EXPECT_LT((moved->urethra[2] - Vec3(10e-3, 4e-3, 10e-3)).norm(), 1e-12);
  // the gland's particles moved with it: the line stays inside the organ
  const Component& c = moved->components[0];
  Vec3 lo = Vec3::Constant(1e9), hi = -lo;
  for (int p = c.first_particle; p < c.first_particle + c.particle_count; ++p) {
    lo = lo.cwiseMin(moved->rest_pos[p]);
    hi = hi.cwiseMax(moved->rest_pos[p]);
  }
  for (const Vec3& u : moved->urethra) EXPECT_TRUE((u.array() > lo.array()).all() && (u.array() < hi.array()).all()) << u.transpose();
  // the ultrasound reads the same line
  EXPECT_EQ(us::build_anatomy(*moved).urethra, moved->urethra);
  // by role, not by name: a gland named otherwise has its urethra; one whose role is not prostate has none
  EXPECT_EQ(compile(mesh_scene(d, "organ", "", "    role: prostate\n"))->urethra.size(), 3u);
  EXPECT_TRUE(compile(mesh_scene(d, "prostate", "", "    role: bladder\n"))->urethra.empty());
  fs::remove_all(d);
}

TEST(Roles, ABadUrethraFileIsRefusedWithItsLine) {
  const fs::path d = cube_with_urethra("bad");
  std::ofstream(d / "urethra.csv") << "x_mm,y_mm,z_mm\n1,2,3\n1,x,3\n";
  try {
    compile(mesh_scene(d, "prostate", ""));
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (d / "urethra.csv").string());
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "y_mm");
  }
  fs::remove_all(d);
}

}  // namespace
}  // namespace ps
