// `prostatesim report DIR... --out DIR2`: a class, not only a trainee. Merges the metrics.json of
// many sessions (each DIR holds one, or sessions below it) into DIR2/sessions.csv and a summary
// picture DIR2/summary.png (score and error distributions, learning curve per trainee;
// app/session/report_chart.cpp). Bad input (a folder without metrics.json, a missing or garbled file)
// exits 2 naming the file and the field, before anything is written.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/commands.h"
#include "app/output_paths.h"
#include "app/session/report_chart.h"
#include "engine/io/png_write.h"
#include "engine/metrics/class_report.h"
#include "engine/util/atomic_file.h"

namespace ps::app {

namespace {
struct ReportArgs {
  std::vector<std::string> folders;
  std::string out = "out/report";
};
}  // namespace

void add_report_command(CLI::App& app, Runner& run) {
  auto args = std::make_shared<ReportArgs>();
  CLI::App* sub = app.add_subcommand("report", "merge many sessions' metrics.json into sessions.csv and summary.png");
  sub->add_option("folders", args->folders, "session folders (metrics.json in each, or in folders below)")->required()->expected(1, -1);
  sub->add_option("--out", args->out, "output folder (created)")->capture_default_str();
  sub->callback([args, &run] {
    run = [args]() -> int {
      const std::vector<MetricsRow> rows = load_sessions(args->folders);
      const auto by = sessions_by_trainee(rows);
      const RgbImage chart = render_report_chart(rows);  // every input checked before anything is written
      prepare_output_dir(args->out, "--out");
      const std::string dir = args->out + "/";
      write_file_atomic(dir + "sessions.csv", sessions_csv(rows));
      write_png_atomic(dir + "summary.png", chart.width, chart.height, 3, chart.pixels.data());
      std::printf("%zu sessions, %zu trainees\n", rows.size(), by.size());
      for (const auto& [trainee, idx] : by) {
        const MetricsRow& a = rows[idx.front()];
        const MetricsRow& b = rows[idx.back()];
        std::printf("  %s: %zu sessions, score %.1f -> %.1f, mean error %.2f -> %.2f mm\n", trainee.c_str(), idx.size(), a.score, b.score,
                    a.mean_error_mm, b.mean_error_mm);
      }
      std::printf("wrote %s{sessions.csv,summary.png}\n", dir.c_str());
      return kExitOk;
    };
  });
}

}  // namespace ps::app
