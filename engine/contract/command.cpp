#include "engine/contract/command.h"

#include <cstring>

namespace ps {

const char* command_kind_name(CommandKind k) {
  switch (k) {
    case CommandKind::ProbeMove: return "probe_move";
    case CommandKind::FillRate: return "fill_rate";
    case CommandKind::FillTo: return "fill_to";
    case CommandKind::NeedleAim: return "needle_aim";
    case CommandKind::NeedleAdvance: return "needle_advance";
    case CommandKind::NeedleRotate: return "needle_rotate";
    case CommandKind::NeedleRelease: return "needle_release";
    case CommandKind::FireGun: return "fire_gun";
    case CommandKind::DepositSeed: return "deposit_seed";
    case CommandKind::SelectNeedle: return "select_needle";
    case CommandKind::SelectHole: return "select_hole";
    case CommandKind::NeedleDepth: return "needle_depth";
  }
  return "?";
}

int command_kind_from_name(const char* name) {
  for (int k = 0; k < kCommandKinds; ++k)
    if (std::strcmp(name, command_kind_name(static_cast<CommandKind>(k))) == 0) return k;
  return -1;
}

}  // namespace ps
