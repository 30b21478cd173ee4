// `prostatesim make-anatomy [--out assets/anatomy]`: generates the default anatomy (engine/anatomy)
// and writes its OBJ/CSV/YAML files; prints each organ's size and volume. The output is a pure
// function of the built-in parameters, so running it again reproduces the committed assets.
// With `--from-labels SEG --labels prostate=1,...` it makes a patient's case instead: organ
// surfaces from a segmentation's label map and a scenario using them (app/labelmap).
#include <cstdio>

#include "app/commands.h"
#include "app/labelmap/patient_case.h"
#include "app/output_paths.h"
#include "engine/anatomy/anatomy_files.h"
#include "engine/anatomy/pelvis.h"
#include "engine/util/error.h"

namespace ps::app {

namespace {

int make_patient_case(const std::string& seg, const std::string& label_text, const std::string& out) {
  if (label_text.empty()) throw InputError("", 0, "--labels", "--from-labels needs --labels, e.g. prostate=1,bladder=2,rectum=3,bone=4,fat=5");
  const auto organs = labelmap::parse_label_list(label_text, "--labels");
  const labelmap::LabelVolume volume = labelmap::read_label_volume(seg);
  const Vec3 s = volume.spacing_m() * 1e3;
  std::printf("%s: %d x %d x %d voxels of %.3g x %.3g x %.3g mm\n", seg.c_str(), volume.size[0], volume.size[1], volume.size[2],
              s.x(), s.y(), s.z());
  const labelmap::PatientCase c = labelmap::make_patient_case(volume, organs);
  prepare_output_dir(out, "--out");
  labelmap::write_patient_case(out, c);
  std::printf("%-9s %7s %9s %12s %12s %7s\n", "organ", "label", "voxels", "voxel cm^3", "surface cm^3", "faces");
  for (const auto& o : c.organs) {
    std::string values;
    for (int v : o.values) values += (values.empty() ? "" : "+") + std::to_string(v);
    std::printf("%-9s %7s %9lld %12.2f %12.2f %7zu\n", o.role.c_str(), values.empty() ? "-" : values.c_str(), o.stats.voxels,
                o.stats.voxel_volume_m3 * 1e6, signed_volume(o.surface) * 1e6, o.surface.faces.size());
  }
  const Vec3 e = c.probe_entry_m * 1e3;
  std::printf("probe entry (%.1f, %.1f, %.1f) mm%s\n", e.x(), e.y(), e.z(),
              c.probe_entry_in_rectum ? " in the rectal lumen" : ": NOT inside the rectum, edit probe.entry_mm");
  std::printf("patient case -> %s/scenario.yaml (patient RAS frame of the label map, mm)\n", out.c_str());
  return kExitOk;
}

}  // namespace

void add_make_anatomy_command(CLI::App& app, Runner& run) {
  auto out = std::make_shared<std::string>("assets/anatomy");
  auto seg = std::make_shared<std::string>();
  auto labels = std::make_shared<std::string>();
  CLI::App* sub = app.add_subcommand("make-anatomy", "generate the default pelvic anatomy meshes (prostate, bladder, rectum, fat, pubic arch; seminal vesicles and the pubic bone as drawn), or a patient's case from a label map");
  sub->add_option("--out", *out, "output folder (created)")->capture_default_str();
  sub->add_option("--from-labels", *seg, "a segmentation's label map (.nrrd, .nhdr, .nii, .nii.gz, as 3D Slicer exports it): writes a patient's case (organ OBJs and scenario.yaml) into --out");
  sub->add_option("--labels", *labels, "with --from-labels: organ=label list, e.g. prostate=1,bladder=2,rectum=3,bone=4,fat=5 (prostate and rectum required; a '+' joins labels: prostate=1+2)");
  sub->callback([out, seg, labels, &run] {
    if (!seg->empty()) {
      run = [out, seg, labels]() -> int { return make_patient_case(*seg, *labels, *out); };
      return;
    }
    run = [out, labels]() -> int {
      if (!labels->empty()) throw InputError("", 0, "--labels", "needs --from-labels");
      prepare_output_dir(*out, "--out");
      const anatomy::Anatomy a = anatomy::generate_anatomy();
      anatomy::write_anatomy_files(*out, a);
      std::printf("default anatomy -> %s (patient RAS frame, mm, origin at the prostate centre)\n", out->c_str());
      std::printf("%-11s %9s %7s %24s\n", "organ", "vol cm^3", "faces", "extent x*y*z mm");
      const std::pair<const char*, const TriMesh*> organs[] = {{"prostate", &a.prostate}, {"bladder", &a.bladder},
                                                                 {"rectum", &a.rectum},     {"fat", &a.fat},
                                                                 {"pubic_arch", &a.pubic_arch},
                                                                 {"sem.vesic.", &a.seminal_vesicles},
                                                                 {"pubic_bone", &a.pubic_bone}};
      for (const auto& [name, m] : organs) {
        Vec3 lo = m->vertices.front(), hi = lo;
        for (const Vec3& v : m->vertices) { lo = lo.cwiseMin(v); hi = hi.cwiseMax(v); }
        const Vec3 e = (hi - lo) * 1e3;
        std::printf("%-11s %9.2f %7zu %8.1f x %5.1f x %5.1f\n", name, signed_volume(*m) * 1e6, m->faces.size(), e.x(), e.y(), e.z());
      }
      std::printf("urethra: %zu points; %zu calcifications; perineal skin plane z = %.1f mm\n", a.urethra.size(), a.calcifications.size(),
                  a.perineum_z * 1e3);
      size_t total = 0;
      for (const auto& f : anatomy::anatomy_files(a)) total += f.contents.size();
      std::printf("wrote %zu files, %.1f KB\n", anatomy::anatomy_files(a).size(), total / 1024.0);
      return kExitOk;
    };
  });
}

}  // namespace ps::app
