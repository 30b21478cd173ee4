// `prostatesim make-anatomy [--out assets/anatomy]`: generates the default anatomy (engine/anatomy)
// and writes its OBJ/CSV/YAML files; prints each organ's size and volume. The output is a pure
// function of the built-in parameters, so running it again reproduces the committed assets.
#include <cstdio>

#include "app/commands.h"
#include "app/output_paths.h"
#include "engine/anatomy/anatomy_files.h"
#include "engine/anatomy/pelvis.h"

namespace ps::app {

void add_make_anatomy_command(CLI::App& app, Runner& run) {
  auto out = std::make_shared<std::string>("assets/anatomy");
  CLI::App* sub = app.add_subcommand("make-anatomy", "generate the default pelvic anatomy meshes (prostate, bladder, rectum, fat, pubic arch)");
  sub->add_option("--out", *out, "output folder (created)")->capture_default_str();
  sub->callback([out, &run] {
    run = [out]() -> int {
      prepare_output_dir(*out, "--out");
      const anatomy::Anatomy a = anatomy::generate_anatomy();
      anatomy::write_anatomy_files(*out, a);
      std::printf("default anatomy -> %s (patient RAS frame, mm, origin at the prostate centre)\n", out->c_str());
      std::printf("%-11s %9s %7s %24s\n", "organ", "vol cm^3", "faces", "extent x*y*z mm");
      const std::pair<const char*, const TriMesh*> organs[] = {{"prostate", &a.prostate}, {"bladder", &a.bladder},
                                                                 {"rectum", &a.rectum},     {"fat", &a.fat},
                                                                 {"pubic_arch", &a.pubic_arch}};
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
