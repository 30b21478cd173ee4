// The registry's one list (engine/tools/tool_kind.h): a new kind adds one line, last.
#include "engine/tools/tool_kind.h"

#include "engine/tools/filling/filling.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe.h"

namespace ps {

const std::vector<const ToolKind*>& tool_kinds() {
  static const std::vector<const ToolKind*> kinds = {
      &NeedleTool::kind(),
      &ProbeTool::kind(),
      &FillingTool::kind(),
  };
  return kinds;
}

}  // namespace ps
