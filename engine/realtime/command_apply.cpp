#include "engine/realtime/command_apply.h"

namespace ps {

std::string RefusalReport::describe() const {
  return "tick " + std::to_string(tick) + ": " + command_kind_name(kind) + " refused: " + text;
}

bool CommandApplier::apply(const Command& c, int64_t tick) {
  const auto& tools = sim_.tools();
  CommandRefusal why;
  int target = c.tool;
  if (target < 0) {
    for (size_t i = 0; i < tools.size() && target < 0; ++i)
      if (tools[i]->accepts(c.kind)) target = static_cast<int>(i);
  }
  bool ok = false;
  if (static_cast<unsigned>(c.kind) >= static_cast<unsigned>(kCommandKinds)) {
    why.set("unknown command kind");
  } else if (target < 0 || target >= static_cast<int>(tools.size())) {
    why.set(c.tool < 0 ? "no instrument in the scene takes this command" : "no such tool");
  } else {
    ok = tools[target]->apply(c, sim_.model(), sim_.state(), why);
  }
  if (!ok) {
    ++refused_;
    RefusalReport r;
    r.tick = tick;
    r.tool = target;
    r.kind = c.kind;
    std::memcpy(r.text, why.text, sizeof r.text);
    refusals_.push(r);
    return false;
  }
  ++applied_;
  if (observer_ || log_) {
    Command done = c;
    done.tick = tick;
    done.tool = static_cast<int16_t>(target);
    if (log_) log_->applied(done);
    if (observer_) observer_->applied(done);
  }
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
    apply(c, tick);
    ++n;
  }
  return n;
}

}  // namespace ps
