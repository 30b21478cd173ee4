// `prostatesim make-anatomy --from-labels` (issue 48, item 3): the default anatomy voxelised at
// 1 mm into a label map, written as Slicer would (NRRD in LPS, NIfTI with an RAS sform), and
// imported back gives each organ's surface within 1.5 mm (95th percentile of the distances both
// ways) and its volume within 3 %; the scenario it writes passes `check` and a short `simulate`.
// Bad label maps exit 2 naming the label, or the file and the field, and write nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "app/labelmap/label_volume.h"
#include "engine/anatomy/pelvis.h"
#include "engine/mesh/mesh_check.h"
#include "engine/mesh/mesh_import.h"
#include "engine/mesh/mesh_query.h"
#include "tests/app/run_cli.h"

namespace {

namespace fs = std::filesystem;
using ps::TriMesh;
using ps::Vec3;
using ps::labelmap::LabelVolume;

const char* kLabels = "prostate=1,bladder=2,rectum=3,bone=4,fat=5";

// The default anatomy's organs with their labels; fat first so the organs overwrite it.
std::vector<std::pair<int, TriMesh>> default_organs() {
  const ps::anatomy::Anatomy a = ps::anatomy::generate_anatomy();
  return {{5, a.fat}, {1, a.prostate}, {2, a.bladder}, {3, a.rectum}, {4, a.pubic_arch}};
}

// Voxel centres on a 1 mm grid offset by half a millimetre from the anatomy's whole-millimetre
// dimensions; a voxel takes the label of the last organ whose surface contains its centre.
LabelVolume voxelise(const std::vector<std::pair<int, TriMesh>>& organs, const Vec3& lo_m, const Vec3& hi_m) {
  LabelVolume v;
  v.index_to_ras_m = ps::Mat3::Identity() * 1e-3;
  v.origin_ras_m = lo_m + Vec3::Constant(0.5e-3);
  for (int a = 0; a < 3; ++a) v.size[a] = static_cast<int>(std::lround((hi_m[a] - lo_m[a]) * 1e3));
  v.labels.assign(static_cast<size_t>(v.size[0]) * v.size[1] * v.size[2], 0);
  for (const auto& [label, mesh] : organs) {
    const ps::MeshQuery q(mesh);
    Vec3 blo = mesh.vertices.front(), bhi = blo;
    for (const Vec3& p : mesh.vertices) {
      blo = blo.cwiseMin(p);
      bhi = bhi.cwiseMax(p);
    }
    int ilo[3], ihi[3];
    for (int a = 0; a < 3; ++a) {
      ilo[a] = std::max(0, static_cast<int>(std::floor((blo[a] - v.origin_ras_m[a]) * 1e3)));
      ihi[a] = std::min(v.size[a] - 1, static_cast<int>(std::ceil((bhi[a] - v.origin_ras_m[a]) * 1e3)));
    }
    for (int k = ilo[2]; k <= ihi[2]; ++k)
      for (int j = ilo[1]; j <= ihi[1]; ++j)
        for (int i = ilo[0]; i <= ihi[0]; ++i)
          if (q.inside(v.ras_m(i, j, k))) v.labels[v.index(i, j, k)] = label;
  }
  return v;
}

// Points spread over a surface: its vertices and its face centroids.
std::vector<Vec3> surface_points(const TriMesh& m) {
  std::vector<Vec3> p = m.vertices;
  for (const auto& f : m.faces) p.push_back((m.vertices[f[0]] + m.vertices[f[1]] + m.vertices[f[2]]) / 3.0);
  return p;
}

// 95th percentile of the distances from each surface's points to the other surface [m].
double p95_distance(const TriMesh& a, const TriMesh& b) {
  const ps::MeshQuery qa(a), qb(b);
  std::vector<double> d;
  for (const Vec3& p : surface_points(a)) d.push_back(qb.distance(p));
  for (const Vec3& p : surface_points(b)) d.push_back(qa.distance(p));
  std::sort(d.begin(), d.end());
  return d[static_cast<size_t>(0.95 * (d.size() - 1))];
}

class PatientCase : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(ps::test::cli_temp_dir("patient_case"));
    const auto organs = default_organs();
    const ps::anatomy::AnatomyParams p;
    const LabelVolume v = voxelise(organs, p.fat_min - Vec3::Constant(3e-3), p.fat_max + Vec3::Constant(3e-3));
    ps::labelmap::write_label_volume_nrrd((*dir_ / "seg.nrrd").string(), v);
    // the NIfTI with its i axis flipped (right -> left), as some exports have it
    LabelVolume f = v;
    f.index_to_ras_m.col(0) *= -1.0;
    f.origin_ras_m.x() = v.ras_m(v.size[0] - 1, 0, 0).x();
    for (int k = 0; k < v.size[2]; ++k)
      for (int j = 0; j < v.size[1]; ++j)
        for (int i = 0; i < v.size[0]; ++i) f.labels[f.index(v.size[0] - 1 - i, j, k)] = v.labels[v.index(i, j, k)];
    ps::labelmap::write_label_volume_nifti((*dir_ / "seg.nii.gz").string(), f);
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path* dir_;
};
fs::path* PatientCase::dir_ = nullptr;

void expect_round_trip(const fs::path& seg, const fs::path& out) {
  const ps::test::CliResult r =
      ps::test::run_cli("make-anatomy --from-labels " + seg.string() + " --labels " + kLabels + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("in the rectal lumen"), std::string::npos) << r.out;
  const std::map<int, std::string> files = {{1, "prostate"}, {2, "bladder"}, {3, "rectum"}, {4, "bone"}, {5, "fat"}};
  for (const auto& [label, original] : default_organs()) {
    const std::string name = files.at(label);
    ps::MeshImportOptions o;
    o.units = "mm";
    const TriMesh m = ps::import_mesh((out / (name + ".obj")).string(), o);
    EXPECT_TRUE(ps::check_mesh(m).valid_solid()) << name << ": " << ps::check_mesh(m).summary();
    const double v0 = ps::signed_volume(original), v1 = ps::signed_volume(m);
    const double p95_mm = p95_distance(original, m) * 1e3;
    std::printf("%s %-8s volume %8.2f -> %8.2f cm^3 (%+.2f %%), p95 distance %.2f mm, %zu faces\n",
                seg.filename().c_str(), name.c_str(), v0 * 1e6, v1 * 1e6, (v1 / v0 - 1) * 100, p95_mm, m.faces.size());
    EXPECT_NEAR(v1 / v0, 1.0, 0.03) << name;
    EXPECT_LT(p95_mm, 1.5) << name;
  }
}

TEST_F(PatientCase, NrrdRoundTripKeepsSurfacesAndVolumes) { expect_round_trip(*dir_ / "seg.nrrd", *dir_ / "nrrd_case"); }

TEST_F(PatientCase, NiftiRoundTripKeepsSurfacesAndVolumes) { expect_round_trip(*dir_ / "seg.nii.gz", *dir_ / "nifti_case"); }

TEST_F(PatientCase, ScenarioPassesCheckAndSimulates) {
  const fs::path out = *dir_ / "sim_case";
  ASSERT_EQ(ps::test::run_cli("make-anatomy --from-labels " + (*dir_ / "seg.nrrd").string() + " --labels " + kLabels + " --out " + out.string()).code, 0);
  // every organ says its role: the case does not depend on its names meaning anything
  std::ifstream yaml(out / "scenario.yaml");
  const std::string text((std::istreambuf_iterator<char>(yaml)), std::istreambuf_iterator<char>());
  for (const char* r : {"prostate", "rectum", "fat"})
    EXPECT_NE(text.find("    role: " + std::string(r) + "\n"), std::string::npos) << r;
  const ps::test::CliResult c = ps::test::run_cli("check " + (out / "scenario.yaml").string());
  ASSERT_EQ(c.code, 0) << c.out;
  EXPECT_EQ(c.out.find("warning"), std::string::npos) << c.out;
  const ps::test::CliResult s = ps::test::run_cli("simulate " + (out / "scenario.yaml").string() + " --duration 0.05 --out " + (out / "run").string());
  ASSERT_EQ(s.code, 0) << s.out;
}

// A label map of its own (8 mm cube of label 1 and 3 inside), for the bad-input cases.
LabelVolume small_volume() {
  LabelVolume v;
  v.size = {12, 12, 12};
  v.index_to_ras_m = ps::Mat3::Identity() * 1e-3;
  v.labels.assign(12 * 12 * 12, 0);
  for (int k = 2; k < 10; ++k)
    for (int j = 2; j < 10; ++j)
      for (int i = 2; i < 10; ++i) v.labels[v.index(i, j, k)] = i < 6 ? 1 : 3;
  return v;
}

ps::test::CliResult make_case(const fs::path& seg, const std::string& labels, const fs::path& out) {
  return ps::test::run_cli("make-anatomy --from-labels " + seg.string() + " --labels " + labels + " --out " + out.string());
}

// exit 2, one message containing every expected piece, no output folder
void expect_refused(const ps::test::CliResult& r, const fs::path& out, const std::vector<std::string>& pieces) {
  EXPECT_EQ(r.code, 2) << r.out;
  for (const auto& p : pieces) EXPECT_NE(r.out.find(p), std::string::npos) << "'" << p << "' not in: " << r.out;
  EXPECT_FALSE(fs::exists(out)) << "wrote " << out;
}

TEST_F(PatientCase, MissingOrEmptyLabelIsNamed) {
  const fs::path seg = *dir_ / "small.nrrd", out = *dir_ / "bad_out";
  ps::labelmap::write_label_volume_nrrd(seg.string(), small_volume());
  expect_refused(make_case(seg, "prostate=1", out), out, {"--labels", "rectum"});
  expect_refused(make_case(seg, "prostate=1,rectum=3,bladder=7", out), out, {"small.nrrd", "bladder (label 7)", "no voxel"});
  expect_refused(make_case(seg, "prostate=1,rectum=3,kidney=4", out), out, {"--labels", "kidney"});
  expect_refused(make_case(seg, "prostate=1,rectum=1", out), out, {"--labels", "label 1"});
  expect_refused(make_case(seg, "prostate=x,rectum=3", out), out, {"--labels", "'x'"});
}

// A NRRD written by hand: raw 4 x 4 x 4 uint8 voxels of label 1 under the given header lines.
fs::path hand_nrrd(const fs::path& dir, const std::string& name, const std::string& lines) {
  const fs::path p = dir / name;
  std::ofstream f(p, std::ios::binary);
  f << "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n" << lines << "\n";
  f << std::string(64, '\1');
  return p;
}

TEST_F(PatientCase, WrongSpacingIsNamed) {
  const fs::path out = *dir_ / "bad_out";
  const std::string lps = "space: left-posterior-superior\nspace origin: (0,0,0)\n";
  struct Bad {
    std::string name, lines, field;
  };
  const std::vector<Bad> bad = {
      {"zero.nrrd", lps + "space directions: (0,0,0) (0,1,0) (0,0,1)\n", "space directions"},
      {"nan.nrrd", lps + "space directions: (1,0,0) (0,nan,0) (0,0,1)\n", ""},
      {"coarse.nrrd", lps + "space directions: (1,0,0) (0,1,0) (0,0,6)\n", "space directions"},
      {"aniso.nrrd", lps + "space directions: (0.3,0,0) (0,0.3,0) (0,0,4)\n", "anisotropy"},
      {"negative.nrrd", "spacings: 1 -1 1\n", "spacings"},
  };
  for (const Bad& b : bad) {
    const fs::path p = hand_nrrd(*dir_, b.name, b.lines);
    std::vector<std::string> pieces = {b.name};
    if (!b.field.empty()) pieces.push_back(b.field);
    expect_refused(make_case(p, "prostate=1,rectum=3", out), out, pieces);
  }
  // NIfTI-1 with no sform and a zero voxel size in pixdim (header bytes 80..: pixdim[1..3])
  const fs::path nii = *dir_ / "zero_pixdim.nii";
  ps::labelmap::write_label_volume_nifti(nii.string(), small_volume());
  {
    std::fstream f(nii, std::ios::in | std::ios::out | std::ios::binary);
    const float zero = 0.0f;
    const short no_sform = 0;
    f.seekp(80);
    f.write(reinterpret_cast<const char*>(&zero), sizeof zero);
    f.seekp(254);
    f.write(reinterpret_cast<const char*>(&no_sform), sizeof no_sform);
  }
  expect_refused(make_case(nii, "prostate=1,rectum=3", out), out, {"zero_pixdim.nii", "pixdim"});
}

TEST_F(PatientCase, UnreadableFileIsNamed) {
  const fs::path out = *dir_ / "bad_out";
  const fs::path junk = *dir_ / "junk.nrrd";
  std::ofstream(junk) << "not a nrrd\n";
  expect_refused(make_case(junk, "prostate=1,rectum=3", out), out, {"junk.nrrd"});
  expect_refused(make_case(*dir_ / "absent.nii.gz", "prostate=1,rectum=3", out), out, {"absent.nii.gz"});
  const fs::path txt = *dir_ / "labels.txt";
  std::ofstream(txt) << "1 2 3\n";
  expect_refused(make_case(txt, "prostate=1,rectum=3", out), out, {"labels.txt", "--from-labels"});
}

}  // namespace
