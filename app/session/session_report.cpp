#include "app/session/session_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "app/plot/chart.h"
#include "engine/metrics/sextant_map.h"

namespace ps::app {

namespace {

constexpr int kW = 800, kH = 600;

void blit(RgbImage& img, const plot::Canvas& c, int x0, int y0) {
  for (int y = 0; y < c.height(); ++y)
    std::copy_n(c.pixels().begin() + static_cast<long>(y) * c.width() * 3, c.width() * 3,
                img.pixels.begin() + (static_cast<long>(y0 + y) * img.width + x0) * 3);
}

std::string f(const char* fmt, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

// Projection of the scene on axes (a, b) of RAS (0 x, 1 y, 2 z) [mm].
plot::Chart scene_view(const Model& m, const State& s, const NeedleTool& tool, const SessionReport& r, int a, int b,
                       const std::string& title, const std::string& xl, const std::string& yl) {
  plot::Chart c;
  c.title = title;
  c.x.label = xl;
  c.y.label = yl;
  c.legend = plot::LegendPos::TopRight;
  auto organ_colour = [](Role role, size_t k) -> plot::Rgb {
    switch (role) {
      case Role::Prostate: return {205, 110, 110};
      case Role::Bladder: return {110, 160, 215};
      case Role::Rectum: return {215, 160, 80};
      case Role::Fat: return {212, 212, 212};
      case Role::Bone: return {160, 110, 170};
      default: return plot::palette(static_cast<int>(k) + 3);
    }
  };
  const int gland = m.find_role(Role::Prostate);
  for (size_t k = 0; k < m.components.size(); ++k) {
    const Component& comp = m.components[k];
    plot::Series p;
    p.label = comp.name;
    p.line = false;
    p.marker = plot::Marker::Circle;
    p.marker_size = comp.name.find("fat") != std::string::npos ? 2.0 : 3.5;
    p.color = organ_colour(comp.role, k);
    for (int i = comp.first_particle; i < comp.first_particle + comp.particle_count; ++i) {
      p.x.push_back(1e3 * s.x[i][a]);
      p.y.push_back(1e3 * s.x[i][b]);
    }
    c.series.push_back(p);
  }
  plot::Series targets, samples, seeds;
  targets.label = "target (carried by the tissue)";
  samples.label = "needle sample (tip / notch centre)";
  seeds.label = "seed";
  targets.line = samples.line = seeds.line = false;
  targets.marker = plot::Marker::Cross;
  samples.marker = plot::Marker::Circle;
  seeds.marker = plot::Marker::Diamond;
  targets.marker_size = samples.marker_size = 12.0;
  seeds.marker_size = 9.0;
  targets.color = {200, 30, 30};
  samples.color = {30, 60, 200};
  seeds.color = {20, 140, 40};
  for (int i = 0; i < tool.count(); ++i) {
    const NeedleMetrics& n = r.needles[i];
    const Vec3 t = n.scored ? n.target_now : n.target_rest;
    targets.x.push_back(1e3 * t[a]);
    targets.y.push_back(1e3 * t[b]);
    plot::Series path;
    path.color = {30, 60, 200};
    path.line_width = 1.5;
    const Vec3 st = tool.spec(i).start;
    const Vec3 end = n.scored ? n.sample : tool.readout(i).tip;
    path.x = {1e3 * st[a], 1e3 * end[a]};
    path.y = {1e3 * st[b], 1e3 * end[b]};
    c.series.push_back(path);
    if (n.scored) {
      samples.x.push_back(1e3 * n.sample[a]);
      samples.y.push_back(1e3 * n.sample[b]);
    }
  }
  for (const SeedReport& sd : tool.seeds())
    if (sd.deposited) {
      seeds.x.push_back(1e3 * sd.current[a]);
      seeds.y.push_back(1e3 * sd.current[b]);
    }
  c.series.push_back(targets);
  c.series.push_back(samples);
  if (!seeds.x.empty()) c.series.push_back(seeds);
  // equal scales: pad the shorter range
  // framed on the gland, the needles and the targets (the whole scene when there is no gland)
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (size_t k = 0; k < c.series.size(); ++k) {
    if (gland >= 0 && k < m.components.size() && static_cast<int>(k) != gland) continue;
    const plot::Series& se = c.series[k];
    for (size_t i = 0; i < se.x.size(); ++i) {
      lo[0] = std::min(lo[0], se.x[i]); hi[0] = std::max(hi[0], se.x[i]);
      lo[1] = std::min(lo[1], se.y[i]); hi[1] = std::max(hi[1], se.y[i]);
    }
  }
  const double aspect = static_cast<double>(kW) / kH;
  double wx = hi[0] - lo[0], wy = hi[1] - lo[1];
  if (wx < wy * aspect) wx = wy * aspect; else wy = wx / aspect;
  const double cx = 0.5 * (lo[0] + hi[0]), cy = 0.5 * (lo[1] + hi[1]);
  c.x.min = cx - 0.7 * wx; c.x.max = cx + 0.7 * wx;
  c.y.min = cy - 0.7 * wy; c.y.max = cy + 0.7 * wy;
  return c;
}

// Cumulative DVH of the prostate, urethra and rectum, achieved (solid) and planned (dashed).
plot::Chart dvh_chart(const DosimetryReport& d) {
  plot::Chart c;
  c.title = f("Dose-volume histogram (TG-43U1, %.0f Gy prescription)", d.prescription_gy);
  c.x.label = "dose [% of prescription]";
  c.y.label = "volume [%]";
  c.x.min = 0.0;
  c.x.max = 250.0;
  c.y.min = 0.0;
  c.y.max = 100.0;
  c.legend = plot::LegendPos::TopRight;
  const plot::Rgb colour[3] = {{200, 40, 40}, {230, 160, 0}, {60, 90, 200}};
  const char* name[3] = {"prostate", "urethra", "rectum"};
  for (int planned = 1; planned >= 0; --planned) {
    const dosimetry::DvhCurve& v = planned ? d.dvh_planned : d.dvh_achieved;
    const std::vector<double>* ys[3] = {&v.prostate, &v.urethra, &v.rectum};
    for (int k = 0; k < 3; ++k) {
      plot::Series s;
      s.label = std::string(name[k]) + (planned ? " plan" : "");
      s.color = colour[k];
      s.dashed = planned;
      for (size_t i = 0; i < v.dose_gy.size(); ++i) {
        s.x.push_back(100.0 * v.dose_gy[i] / d.prescription_gy);
        s.y.push_back(100.0 * (*ys[k])[i]);
      }
      c.series.push_back(s);
    }
  }
  return c;
}

// The dose-volume indices, planned beside achieved.
plot::Canvas dosimetry_table(const DosimetryReport& d) {
  plot::Canvas t(kW, kH);
  const plot::Rgb dim{90, 90, 90};
  int y = 20;
  auto line = [&](const std::string& s, int scale = 2, plot::Rgb c = {20, 20, 20}) {
    t.text(24, y, s, c, scale);
    y += plot::Canvas::text_height(scale) + 8;
  };
  line("Implant dosimetry", 3);
  line(d.isotope + f(" seeds of %.3f U, prescription %.0f Gy", d.strength_u, d.prescription_gy), 2, dim);
  line(f("seeds deposited %.0f of %.0f planned", d.seeds_deposited, d.seeds_planned), 2, dim);
  line("                      planned   achieved", 2, dim);
  const auto& p = d.planned;
  const auto& a = d.achieved;
  line(f("prostate D90  [Gy]   %7.1f   %7.1f", p.prostate_d90_gy, a.prostate_d90_gy));
  line(f("prostate V100 [%%]    %7.1f   %7.1f", 100 * p.prostate_v100, 100 * a.prostate_v100));
  line(f("prostate V150 [%%]    %7.1f   %7.1f", 100 * p.prostate_v150, 100 * a.prostate_v150));
  line(f("prostate V200 [%%]    %7.1f   %7.1f", 100 * p.prostate_v200, 100 * a.prostate_v200));
  line(f("urethra D10   [Gy]   %7.1f   %7.1f", p.urethra_d10_gy, a.urethra_d10_gy));
  line(f("urethra D30   [Gy]   %7.1f   %7.1f", p.urethra_d30_gy, a.urethra_d30_gy));
  line(f("rectum D2cc   [Gy]   %7.1f   %7.1f", p.rectum_d2cc_gy, a.rectum_d2cc_gy));
  line(f("rectum V100   [cc]   %7.2f   %7.2f", p.rectum_v100_cc, a.rectum_v100_cc));
  line(f("prostate %.1f cc on a 1 mm grid (gland + 10 mm)", a.prostate_cc), 1, dim);
  return t;
}

}  // namespace

// The 12-core map (engine/metrics/sextant_map.h) at (x0, y0): planned sites outlined, cored
// sites green (the number of cores), a core that held lesion red.
void draw_sextant_map(plot::Canvas& t, const SextantMap& map, int lesions_targeted, int lesions_missed, int x0, int y0) {
  constexpr int kCw = 52, kCh = 30;
  const plot::Rgb ink{20, 20, 20}, dim{110, 110, 110};
  t.text(x0, y0, "12-core map", ink, 2);
  y0 += 22;
  const char* cols[4] = {"R lat", "R med", "L med", "L lat"};
  const char* rows[3] = {"base", "mid", "apex"};
  for (int c = 0; c < 4; ++c) t.text(x0 + 40 + c * kCw + 6, y0, cols[c], dim, 1);
  y0 += 12;
  for (int r = 0; r < 3; ++r) {
    t.text(x0, y0 + r * kCh + 11, rows[r], dim, 1);
    for (int c = 0; c < 4; ++c) {
      const SextantCell& cell = map.cells[4 * r + c];
      const int cx = x0 + 40 + c * kCw, cy = y0 + r * kCh;
      if (cell.cores > 0) t.fill_rect(cx + 2, cy + 2, cx + kCw - 2, cy + kCh - 2, cell.lesion ? plot::Rgb{215, 60, 50} : plot::Rgb{80, 170, 90});
      else if (cell.planned) t.fill_rect(cx + 2, cy + 2, cx + kCw - 2, cy + kCh - 2, {232, 232, 232});
      t.rect_outline(cx + 1, cy + 1, cx + kCw - 1, cy + kCh - 1, cell.planned ? ink : plot::Rgb{200, 200, 200});
      if (cell.cores > 0) t.text(cx + kCw / 2 - 4, cy + 9, std::to_string(cell.cores), {255, 255, 255}, 2);
    }
  }
  int y = y0 + 3 * kCh + 6;
  t.text(x0, y, "green: cored  red: lesion  grey: planned, missed", dim, 1);
  y += 12;
  if (map.off_map > 0) { t.text(x0, y, f("%.0f core(s) off the map (outside the gland)", map.off_map), {160, 40, 40}, 1); y += 12; }
  if (lesions_targeted > 0) t.text(x0, y, f("lesions: %.0f targeted, %.0f missed", lesions_targeted, lesions_missed), lesions_missed ? plot::Rgb{160, 40, 40} : ink, 1);
}

RgbImage render_session_report(const Model& m, const State& s, const NeedleTool& tool, const ForceDepthRecorder& rec,
                               const SessionReport& r, const Score& score, const ReportViews* views) {
  // force versus depth
  plot::Chart fd;
  fd.title = "Force versus depth (punctures marked)";
  fd.x.label = "insertion depth [mm]";
  fd.y.label = "axial force on the needle [N]";
  fd.legend = plot::LegendPos::TopLeft;
  plot::Series punct;
  punct.label = "puncture";
  punct.line = false;
  punct.marker = plot::Marker::Triangle;
  punct.marker_size = 12.0;
  punct.color = {200, 30, 30};
  for (int i = 0; i < tool.count(); ++i) {
    plot::Series l;
    l.label = tool.spec(i).name;
    l.color = plot::palette(i);
    for (const ForceDepthSample& q : rec.samples(i))
      if (q.contacted) {
        l.x.push_back(1e3 * q.depth);
        l.y.push_back(q.axial_force);
      }
    fd.series.push_back(l);
  }
  for (const NeedleEvent& e : tool.events().snapshot())
    if (e.kind == NeedleEventKind::Puncture) {
      punct.x.push_back(1e3 * e.depth);
      punct.y.push_back(e.force);
    }
  if (!punct.x.empty()) fd.series.push_back(punct);

  RgbImage img;
  const int col = views ? 2 : 1;  // column of the projections
  img.width = (col + 1) * kW;
  img.height = (r.dosimetry.computed ? 3 : 2) * kH;  // a third row: the implant's DVH and indices
  img.pixels.assign(static_cast<size_t>(img.width) * img.height * 3, 255);
  blit(img, plot::render(fd, kW, kH), 0, 0);
  blit(img, plot::render(scene_view(m, s, tool, r, 1, 2, "Sagittal view at the end (y-z)", "y, anterior [mm]", "z, superior [mm]"), kW, kH),
       col * kW, 0);
  blit(img, plot::render(scene_view(m, s, tool, r, 0, 2, "Coronal view at the end (x-z)", "x, patient right [mm]", "z, superior [mm]"), kW, kH),
       col * kW, kH);
  if (views) {
    if (views->view3d.width == kW && views->view3d.height == kH) {
      for (int y = 0; y < kH; ++y)
        std::copy_n(views->view3d.pixels.begin() + static_cast<long>(y) * kW * 3, kW * 3,
                    img.pixels.begin() + (static_cast<long>(y) * img.width + kW) * 3);
    } else {
      plot::Canvas v3(kW, kH);
      v3.text(24, kH / 2 - 20, "3D view", {20, 20, 20}, 3);
      v3.text(24, kH / 2 + 20, views->note3d.substr(0, 70), {160, 40, 40}, 2);
      if (views->note3d.size() > 70) v3.text(24, kH / 2 + 44, views->note3d.substr(70, 70), {160, 40, 40}, 2);
      blit(img, v3, kW, 0);
    }
    plot::Canvas us(kW, kH);
    us.text(16, 10, "Ultrasound at the punctures and cores", {20, 20, 20}, 2);
    if (views->punctures.empty()) us.text(16, kH / 2, views->note_us, {120, 120, 120}, 2);
    for (size_t k = 0; k < views->punctures.size() && k < 4; ++k) {
      const PunctureShot& p = views->punctures[k];
      const int x0 = 16 + static_cast<int>(k % 2) * (kW / 2), y0 = 40 + static_cast<int>(k / 2) * (kH / 2 - 14);
      const int side = std::min(kW / 2 - 32, kH / 2 - 60);
      // nearest-neighbour scale of the grayscale image into side x side
      for (int y = 0; y < side && p.us.height > 0; ++y)
        for (int x = 0; x < side; ++x) {
          const int sx = x * p.us.width / side, sy = y * p.us.height / side;
          const uint8_t* q = &p.us.pixels[3 * (static_cast<size_t>(sy) * p.us.width + sx)];
          us.blend(x0 + x, y0 + y, {q[0], q[1], q[2]}, 1.0);
        }
      us.text(x0, y0 + side + 4, p.needle + " " + (p.organ == "core" ? std::string("core") : "puncture " + p.organ) +
                                     f(" %.2f s, %.1f mm, %.2f N", p.time, 1e3 * p.depth, p.force), {20, 20, 20}, 1);
    }
    blit(img, us, kW, kH);
  }

  // the numbers
  plot::Canvas t(kW, kH);
  const plot::Rgb ink{20, 20, 20}, dim{90, 90, 90};
  int y = 20;
  auto line = [&](const std::string& s, int scale = 2, plot::Rgb c = {20, 20, 20}) {
    if (scale == 2 && plot::Canvas::text_width(s, 2) > kW - 40) scale = 1;  // a long line in the small font, not cut
    t.text(24, y, s, c, scale);
    y += plot::Canvas::text_height(scale) + (scale > 2 ? 14 : 8);
  };
  line("Session: " + r.scenario + f("   simulated %.2f s", r.duration), 2, dim);
  line(f("SCORE %.1f / 100", score.value), 4);
  for (const ScoreTerm& st : score.terms) line(f("  -%.1f  ", st.points) + st.name + ": " + st.detail, 2, st.points > 0 ? ink : dim);
  y += 6;
  const std::string scale = han_scale_text(r.mean_error);
  const size_t cite = scale.find(" (Han");
  const std::string head = scale.substr(0, cite);
  const size_t colon = head.find(": ");
  line("Targeting error " + head.substr(0, colon), 2);
  if (colon != std::string::npos) line("  " + head.substr(colon + 2), 2);
  if (cite != std::string::npos) line("  scale:" + scale.substr(cite), 2, dim);
  line(std::isnan(r.max_error) ? std::string("") : f("max error %.2f mm, procedure time %.2f s, %.0f punctures, %.0f re-insertions", 1e3 * r.max_error,
                                                     r.procedure_time, r.punctures, r.reinsertions));
  // the scale bar: robot 1.0 mm ... freehand 9.0 mm, and the trainee
  const int x0 = 60, x1 = kW - 60, yb = y + 24;
  auto xs = [&](double mm) { return x0 + (x1 - x0) * std::clamp(mm / 12.0, 0.0, 1.0); };
  t.line(x0, yb, x1, yb, dim, 2.0);
  for (int k = 0; k <= 12; k += 2) {
    t.line(xs(k), yb - 5, xs(k), yb + 5, dim, 1.0);
    t.text(static_cast<int>(xs(k)) - 4, yb + 10, std::to_string(k), dim, 1);
  }
  t.fill_circle(xs(1.0), yb, 7, {40, 150, 60});
  t.text(static_cast<int>(xs(1.0)) - 20, yb - 28, "robot 1.0", {40, 150, 60}, 2);
  t.fill_circle(xs(9.0), yb, 7, {200, 40, 40});
  t.text(static_cast<int>(xs(9.0)) - 40, yb - 28, "freehand 9.0", {200, 40, 40}, 2);
  if (!std::isnan(r.mean_error)) {
    t.marker(plot::Marker::Diamond, xs(1e3 * r.mean_error), yb, 16, {30, 60, 200});
    t.text(static_cast<int>(xs(1e3 * r.mean_error)) - 30, yb + 24, f("you %.1f mm", 1e3 * r.mean_error), {30, 60, 200}, 2);
  }
  y = yb + 56;
  line("needle        error  lateral  depth  peak N  mean N  time s  hits", 2, dim);
  for (const NeedleMetrics& n : r.needles) {
    std::string hits;
    for (const std::string& h : n.structures_hit) hits += (hits.empty() ? "" : ", ") + h;
    std::string name = n.name.substr(0, 12);
    name.resize(12, ' ');
    line(name + (n.scored ? f(" %6.2f  %6.2f  %6.2f", 1e3 * n.error, 1e3 * n.lateral_error, 1e3 * n.depth_error) : std::string("    (not inserted)    ")) +
         f("  %5.2f  %5.2f  %6.2f  ", n.peak_force, n.mean_force, std::isnan(n.insertion_time) ? 0.0 : n.insertion_time) + hits);
    if (y > kH - 40) break;
  }
  if (!r.cores.empty()) {
    int hit = 0;
    for (const CoreMetrics& c : r.cores) hit += c.lesion_hit;
    line(f("cores %.0f, lesion in %.0f", r.cores.size(), hit) + (std::isnan(r.coverage) ? std::string() : f(", coverage %.0f %%", 100 * r.coverage)));
  }
  if (!std::isnan(r.seed_error_mean))
    line(f("seeds %.0f: error mean %.2f mm, max %.2f mm; outside the gland %.0f", r.seeds.size(), 1e3 * r.seed_error_mean,
           1e3 * r.seed_error_max, r.seeds_outside_gland));
  if (!r.planned_sites.empty() || !r.cores.empty())
    draw_sextant_map(t, sextant_map(r), r.lesions_targeted, r.lesions_missed, kW - 270, 16);
  if (!std::isnan(r.probe_peak_force))
    line(f("probe contact force: peak %.1f N, %.1f s above %.0f N (provisional threshold)", r.probe_peak_force, r.probe_time_above,
           kProbeForceThreshold));
  blit(img, t, 0, kH);
  if (r.dosimetry.computed) {
    blit(img, plot::render(dvh_chart(r.dosimetry), kW, kH), 0, 2 * kH);
    blit(img, dosimetry_table(r.dosimetry), kW, 2 * kH);
  }
  return img;
}

}  // namespace ps::app
