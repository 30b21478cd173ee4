// The probe's panel: its pose as sliders and its contact force on the rectal wall, with the time
// spent above the metrics' threshold (kProbeForceThreshold, provisional: no source gives one).
#include <imgui.h>

#include <algorithm>

#include "app/gui/session.h"
#include "app/gui/tool_panels.h"
#include "engine/metrics/session_metrics.h"
#include "engine/tools/probe/probe.h"
#include "engine/tools/tool_kind.h"

namespace ps::gui {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

void ProbePanelState::reset(const ProbePose& p) {
  insertion_mm = static_cast<float>(p.insertion * 1e3);
  roll_deg = static_cast<float>(p.roll * 180 / kPi);
  tilt_deg = static_cast<float>(p.tilt * 180 / kPi);
  yaw_deg = static_cast<float>(p.yaw * 180 / kPi);
}

void ProbePanelState::command(Session& s) const {
  s.move_probe(insertion_mm * 1e-3, roll_deg * kPi / 180, tilt_deg * kPi / 180, yaw_deg * kPi / 180);
}

void probe_controls(Session& s, const Snapshot& snap, ToolPanelState& st) {
  ProbePanelState& p = st.probe;
  ImGui::Text("Probe pose");
  bool moved = false;
  moved |= ImGui::SliderFloat("insertion [mm]", &p.insertion_mm, 0.0f, 80.0f);
  moved |= ImGui::SliderFloat("roll [deg]", &p.roll_deg, -90.0f, 90.0f);
  moved |= ImGui::SliderFloat("tilt [deg]", &p.tilt_deg, -20.0f, 20.0f);
  moved |= ImGui::SliderFloat("yaw [deg]", &p.yaw_deg, -20.0f, 20.0f);
  if (moved) p.command(s);
  for (const auto& t : snap.tools) {
    if (t.kind != tool_kind_index(ProbeTool::kind())) continue;
    if (snap.time < p.time) { p.peak_n = 0; p.above_s = 0; }  // restarted
    if (t.force > kProbeForceThreshold && snap.time > p.time) p.above_s += snap.time - p.time;
    p.time = snap.time;
    p.peak_n = std::max(p.peak_n, t.force);
    const bool high = t.force > kProbeForceThreshold;
    ImGui::TextColored(high ? ImVec4(1, 0.45f, 0.35f, 1) : ImVec4(0.8f, 0.85f, 0.9f, 1), "contact force %.1f N (peak %.1f N)", t.force,
                       p.peak_n);
    ImGui::Text("%.1f s above %.0f N (provisional)", p.above_s, kProbeForceThreshold);
  }
  ImGui::Separator();
}

}  // namespace ps::gui
