// Reader side of a ToolReportRing (engine/tools/tool_reports.h): the lines a CLI prints and the
// snapshot events the app shows, formatted from the records by the tool's own `describe`. Never
// called on the physics thread (it allocates strings); shared by FillingTool and ProbeTool.
#pragma once
#include <algorithm>
#include <string>
#include <vector>

#include "engine/contract/snapshot.h"
#include "engine/tools/tool_reports.h"

namespace ps {

// every record still held, oldest first, after a line saying how many were dropped; `what` names
// the tool ("filling", "probe"); describe(record, buffer, size, brief) writes one sentence
template <class Describe>
std::vector<std::string> report_lines(const ToolReportRing& ring, const char* what, Describe describe) {
  std::vector<std::string> out;
  if (ring.dropped() > 0)
    out.push_back(std::to_string(ring.dropped()) + " earlier " + what + " reports were dropped (ring of " +
                  std::to_string(ToolReportRing::kCapacity) + ")");
  char b[320];
  for (int i = 0; i < ring.size(); ++i) {
    describe(ring.at(i), b, sizeof b, false);
    out.emplace_back(b);
  }
  return out;
}

// the records from number `cursor` on as kSnapshotEventAdjusted events of tool `tool_index`
// (brief text) while `out` holds fewer than max_size; returns the cursor for the next call (the
// first record not appended)
template <class Describe>
int64_t report_events(const ToolReportRing& ring, int64_t cursor, int tool_index, std::vector<SnapshotEvent>& out,
                      size_t max_size, Describe describe) {
  for (int64_t k = std::max(cursor, ring.dropped()); k < ring.total(); ++k) {
    if (out.size() >= max_size) return k;
    const ToolReport& r = ring.record(k);
    SnapshotEvent e;
    e.time = r.time;
    e.tool = tool_index;
    e.kind = kSnapshotEventAdjusted;
    describe(r, e.text.data(), e.text.size(), true);
    out.push_back(e);
  }
  return ring.total();
}

}  // namespace ps
