// One parsed entry of a script's timeline (or one live command: the same keys without `t`).
// Plain data: the instrument kind that owns the entry's action fills it (engine/tools/tool_kind.h)
// and turns it into that kind's command once the scene is known. Lengths in m, angles in rad.
#pragma once
#include <string>

#include "engine/util/vec.h"

namespace ps {

struct ScriptEntry {
  double t = 0.0;                  // [s]
  int line = 0;                    // in the script file
  std::string action;              // the timeline key, one of a kind's actions (probe, needle, fill_to, ...)
  std::string target;              // needle name / organ name ("" for the probe)
  // probe (fields not given keep the previous commanded value)
  bool has_insertion = false, has_offset = false, has_roll = false, has_tilt = false, has_yaw = false;
  double insertion = 0.0;          // [m]
  Vec3 offset = Vec3::Zero();      // [m]
  double roll = 0.0, tilt = 0.0, yaw = 0.0;  // [rad]
  double over = 0.0;               // probe move / fill_to duration [s]
  // needle
  double depth = 0.0;              // needle key: depth along its path [m]
  double speed = 0.0;              // advance [m/s]
  double angle = 0.0;              // rotate [rad]
  int col = 0, row = 0;            // hole
  double value = 0.0;              // fill_rate [m^3/s], fill_to [m^3]
};

}  // namespace ps
