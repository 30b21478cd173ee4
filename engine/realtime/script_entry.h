// One timeline entry as a command (engine/realtime/script.h has the format): what
// script_commands does for each entry of a file, and what a live command of the Python module
// (python/session.h: Scene.command) goes through, so both get the same checks and errors.
#pragma once
#include <cstdint>
#include <string>

#include "engine/realtime/script.h"
#include "engine/tools/tool_kind.h"

namespace ps {

// A live command: the keys of one timeline entry without `t`, as YAML or JSON text, checked as a
// script entry is. InputError naming the key as `where`.key (the file left empty).
ScriptEntry parse_command_text(const std::string& text, const std::string& where = "command");

// The command of one entry for a scene, stamped `tick`, made by the instrument kind that takes
// the entry's action (engine/tools/tool_kind.h). `memory` carries what the kinds remember along a
// timeline (the probe pose commanded so far: a probe entry's missing fields keep it); `timeline`
// and `index`, when given, let a needle depth key move on at the speed that reaches its next key.
// InputError (file:line) for an instrument the scene lacks.
Command entry_command(const ScriptEntry& e, const Scene& scene, int64_t tick, TimelineMemory& memory, const std::string& file,
                      const std::vector<ScriptEntry>* timeline = nullptr, size_t index = 0);

}  // namespace ps
