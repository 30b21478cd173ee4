#include "engine/realtime/command_apply.h"

#include "engine/tools/filling.h"
#include "engine/tools/probe.h"
#include "engine/util/error.h"

namespace ps {

bool CommandApplier::apply(const Command& c) {
  auto refuse = [&](const std::string& why) {
    ++refused_;
    reports_.push_back("tick " + std::to_string(c.tick) + ": command refused: " + why);
    return false;
  };
  try {
    switch (c.kind) {
      case CommandKind::ProbeMove: {
        if (!probe_) return refuse("no probe in the scene");
        ProbePose p;
        p.insertion = c.insertion;
        p.offset = Vec3(c.offset[0], c.offset[1], c.offset[2]);
        p.roll = c.roll;
        p.tilt = c.tilt;
        p.yaw = c.yaw;
        probe_->move_to(p, c.duration);
        break;
      }
      case CommandKind::FillRate:
      case CommandKind::FillTo: {
        if (!filling_) return refuse("no filling in the scene");
        if (c.component < 0 || c.component >= static_cast<int>(m_.components.size()))
          return refuse("component index " + std::to_string(c.component) + " out of range");
        const std::string& name = m_.components[c.component].name;
        if (c.kind == CommandKind::FillRate) filling_->set_rate(name, c.value);
        else filling_->fill_to(name, c.value, c.duration);
        break;
      }
      default:
        return refuse("unknown command kind");
    }
  } catch (const InputError& e) {
    return refuse(e.what());
  }
  ++applied_;
  return true;
}

int CommandApplier::apply_due(CommandQueue& q, int64_t tick, bool* complete) {
  int n = 0;
  Command c;
  if (complete) *complete = false;
  while (q.peek(c)) {
    if (c.tick > tick) {
      if (complete) *complete = true;
      break;
    }
    q.pop(c);
    if (c.tick < tick) ++late_;
    apply(c);
    ++n;
  }
  return n;
}

}  // namespace ps
