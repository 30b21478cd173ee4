#include "engine/realtime/tick_runner.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "engine/util/error.h"

namespace ps {

TickRunner::TickRunner(Simulation& sim, size_t queue_capacity)
    : sim_(sim), queue_(queue_capacity), applier_(sim), event_cursor_(sim.tools().size(), 0) {
  sim_.save(initial_);
}

void TickRunner::keep_last_good(bool on) {
  keep_good_ = on;
  if (on) {
    log_.cmds.reserve(kLogCapacity);
    applier_.set_log(&log_);
    take_checkpoint();  // sized once here; later checkpoints reuse the capacity
  } else {
    applier_.set_log(nullptr);
  }
}

void TickRunner::take_checkpoint() {
  sim_.save(checkpoint_);
  checkpoint_tick_ = tick_;
  log_.cmds.clear();
  log_.full = false;
}

bool TickRunner::last_good(SavedState& out) {
  if (!keep_good_) return false;
  double time = sim_.state().time;
  if (!faulted_ && !in_step_) {
    sim_.save(out.bytes);  // between ticks: the current state is the one before tick_
  } else {
    // the state after tick_ ticks, before tick_'s commands: from the checkpoint, the same
    // commands at the same ticks, the same bits; then the faulted state is put back
    std::vector<uint8_t> now;
    sim_.save(now);
    try {
      sim_.restore(checkpoint_);
      CommandApplier again(sim_);  // no observer: the recorder has these commands already
      size_t k = 0;
      const std::vector<Command>& log = log_.cmds;
      for (int64_t t = checkpoint_tick_; t < tick_; ++t) {
        for (; k < log.size() && log[k].tick <= t; ++k) again.apply(log[k], t);
        if (!sim_.tick()) break;  // these ticks ran clean before: not reached
      }
      sim_.save(out.bytes);
      time = sim_.state().time;
    } catch (...) {
      sim_.restore(now);  // the faulted state as it was, whatever happened
      throw;
    }
    sim_.restore(now);
  }
  out.tick = tick_;
  out.time = time;
  out.state_hash = saved_state_hash(out.bytes);
  out.fault = fault_text_.empty() ? "none" : fault_text_;
  return true;
}

bool TickRunner::step(StageProbe* probe) {
  if (faulted_) return false;
  // a checkpoint before the commands: the state after tick_ ticks (state_file.h)
  if (keep_good_ && (tick_ - checkpoint_tick_ >= kCheckpointTicks || log_.full)) take_checkpoint();
  in_step_ = true;
  for (CommandSource* s : sources_) s->poll(tick_, sim_, applier_);
  applier_.apply_due(queue_, tick_);
  if (tick_ == inject_tick_) {  // once: a reset after the fault runs on clean
    inject_tick_ = -1;
    if (inject_internal_) throw std::logic_error("injected internal error at tick " + std::to_string(tick_) + " (test hook)");
    State& st = sim_.state();
    if (inject_particle_ >= 0 && inject_particle_ < static_cast<int>(st.x.size()))
      st.x[inject_particle_].x() = std::numeric_limits<double>::quiet_NaN();
  }
  const int64_t at = tick_;
  bool ok = sim_.tick(probe);
  const Model& m = sim_.model();
  char head[96];
  if (!ok) {
    std::snprintf(head, sizeof head, "tick %lld: ", static_cast<long long>(at));
    fault_text_ = head + sim_.state().fault.describe(m);
  } else if (watchdog_) {
    const WatchFinding f = watchdog_->check(m, sim_.state());
    if (!f.ok) {
      ok = false;
      std::snprintf(head, sizeof head, "tick %lld: watchdog: ", static_cast<long long>(at));
      fault_text_ = head + f.describe(m);
    }
  }
  in_step_ = false;
  if (!ok) {
    faulted_ = true;
    return false;
  }
  ++tick_;
  for (CommandSource* s : sources_) s->after_tick(tick_, sim_);
  if (hash_observer_ && hash_every_ > 0) {
    if (hash_tick_ >= 0) advance_hash(false);
    if (tick_ % hash_every_ == 0) {
      if (!spread_) {
        hash_observer_->state_hash(tick_, sim_.hash());
      } else {
        if (hash_tick_ >= 0) advance_hash(true);  // the previous one, if a slice was short (it is not: hash_every / 2 ticks)
        sim_.save(hash_buf_);                      // the capacity sized in spread_hashes(): no allocation
        hash_tick_ = tick_;
        hash_pos_ = 0;
        hash_h_ = fnv1a(nullptr, 0);
      }
    }
  }
  return true;
}

void TickRunner::spread_hashes(bool on) {
  spread_ = on;
  if (on) sim_.save(hash_buf_);
  hash_tick_ = -1;
}

void TickRunner::advance_hash(bool to_end) {
  const size_t n = hash_buf_.size();
  const size_t slices = static_cast<size_t>(std::max(1, hash_every_ / 2));
  const size_t chunk = to_end ? n - hash_pos_ : std::min(n - hash_pos_, (n + slices - 1) / slices);
  hash_h_ = fnv1a(hash_buf_.data() + hash_pos_, chunk, hash_h_);
  hash_pos_ += chunk;
  if (hash_pos_ < n) return;
  const int64_t t = hash_tick_;
  hash_tick_ = -1;
  if (hash_observer_) hash_observer_->state_hash(t, hash_h_);
}

void TickRunner::finish_hashes() {
  if (hash_tick_ >= 0) advance_hash(true);
}

void TickRunner::reset() {
  sim_.restore(initial_);
  hash_tick_ = -1;  // a hash under way belonged to the run that is gone
  tick_ = 0;
  faulted_ = false;
  in_step_ = false;
  fault_text_.clear();
  if (keep_good_) keep_last_good(true);
  Command c;
  while (queue_.pop(c)) {
  }
  for (CommandSource* s : sources_) s->rewind();
  std::fill(event_cursor_.begin(), event_cursor_.end(), 0);
}

void TickRunner::current_state(SavedState& out) {
  sim_.save(out.bytes);
  out.tick = tick_;
  out.time = sim_.state().time;
  out.state_hash = saved_state_hash(out.bytes);
  out.fault = faulted_ ? fault_text_ : "none";
}

void TickRunner::load_state(const SavedState& st) {
  if (saved_state_hash(st.bytes) != st.state_hash)
    throw InputError(st.file, 7, "state_hash", "the saved bytes do not match their hash (the file is damaged)");
  std::vector<uint8_t> before;
  sim_.save(before);
  try {
    sim_.restore(st.bytes);
  } catch (const std::exception& e) {
    sim_.restore(before);  // nothing changed
    throw InputError(st.file, 9, "bytes", std::string("does not fit this scenario's simulation (") + e.what() + ")");
  }
  tick_ = st.tick;
  hash_tick_ = -1;
  faulted_ = false;
  in_step_ = false;
  fault_text_.clear();
  Command c;
  while (queue_.pop(c)) {
  }
  for (CommandSource* s : sources_) s->seek(tick_);
  // the events already in the restored state are not news
  std::vector<SnapshotEvent> old;
  const auto& tools = sim_.tools();
  for (size_t i = 0; i < tools.size(); ++i) event_cursor_[i] = tools[i]->events_since(0, static_cast<int>(i), old, std::numeric_limits<size_t>::max());
  if (keep_good_) keep_last_good(true);
}

void TickRunner::fill_snapshot(Snapshot& out, bool keep_events, bool with_hash, size_t max_events) {
  const Model& m = sim_.model();
  const State& s = sim_.state();
  out.tick = tick_;
  out.time = s.time;
  out.x.resize(3 * s.x.size());
  for (size_t i = 0; i < s.x.size(); ++i) {
    out.x[3 * i] = static_cast<float>(s.x[i].x());
    out.x[3 * i + 1] = static_cast<float>(s.x[i].y());
    out.x[3 * i + 2] = static_cast<float>(s.x[i].z());
  }
  out.draw.clear();
  const auto& tools = sim_.tools();
  out.tools.resize(tools.size());
  if (!keep_events) out.events.clear();
  const size_t carried = out.events.size();
  for (size_t i = 0; i < tools.size(); ++i) {
    tools[i]->draw(out.draw, m, s);
    ToolReadout& r = out.tools[i];
    r = ToolReadout{};
    std::snprintf(r.name.data(), r.name.size(), "%s", tools[i]->name());
    tools[i]->readout(r, m, s);
    event_cursor_[i] = tools[i]->events_since(event_cursor_[i], static_cast<int>(i), out.events, max_events);
  }
  // refused commands are events too (the trainee sees why nothing happened)
  const RefusalRing& rr = applier_.refusals();
  int64_t k = std::max(refusal_cursor_, rr.total() - rr.size());
  for (; k < rr.total() && out.events.size() < max_events; ++k) {
    const RefusalReport& r = rr.at(static_cast<int>(rr.size() - (rr.total() - k)));
    SnapshotEvent e;
    e.time = s.time;
    e.tool = r.tool;
    e.kind = kSnapshotEventRefused;
    std::snprintf(e.text.data(), e.text.size(), "%s refused: %s", command_kind_name(r.kind), r.text);
    out.events.push_back(e);
  }
  refusal_cursor_ = k;
  for (size_t k = carried; k < out.events.size(); ++k) out.events[k].seq = ++event_seq_;
  out.state_hash = with_hash ? sim_.hash() : 0;
  out.faulted = faulted_ || s.fault.kind != StepFault::None;
  out.fault.fill(0);
  if (out.faulted)
    std::snprintf(out.fault.data(), out.fault.size(), "%s", fault_text_.empty() ? s.fault.describe(m).c_str() : fault_text_.c_str());
}

}  // namespace ps
