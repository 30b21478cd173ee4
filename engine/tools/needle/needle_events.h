// Needle events (contact, puncture, stick<->slip, seed, core, bone hit, force clamp) stamped with
// the simulation time, kept in a ring buffer sized once: pushing inside a step never allocates;
// when full the oldest event is overwritten and counted as dropped.
#pragma once
#include <cstdint>
#include <vector>

#include "engine/util/vec.h"

namespace ps {

enum class NeedleEventKind : uint8_t {
  Contact,      // tip first touches tissue of a component
  Puncture,     // a component's surface (capsule, wall, skin) breached: depth, force (total axial, peak since
                // the previous puncture), value = the contact force on the surface at rupture [N]
  Stick,        // a node's virtual tissue particle went from slip to stick (node)
  Slip,         // ... from stick to slip (node)
  Seed,         // seed deposited (value = seed index; component = -1 when no tissue held it)
  Core,         // biopsy core taken (value = particles in the notch; details in NeedleTool::core)
  BoneHit,      // tip stopped by rigid bone (component, position)
  ForceClamped, // coupling force or speed exceeded the needle's limit and was clamped
  Urethra,      // tip came within the urethra's radius of its centre line (value: distance [m])
  GlandExit     // tip, in through the gland's capsule, went out through its surface again (component:
                // the gland)
};
const char* needle_event_name(NeedleEventKind k);

struct NeedleEvent {
  NeedleEventKind kind = NeedleEventKind::Contact;
  int needle = -1;
  double time = 0.0;               // simulation time [s]
  Vec3 position = Vec3::Zero();    // tip (or seed / contact point) [m]
  double depth = 0.0;              // insertion depth since first contact [m]
  double force = 0.0;              // axial tissue force on the needle at the event [N]
  int component = -1;              // Model component, -1 if none
  int node = -1;                   // needle node for stick/slip
  double value = 0.0;              // event-specific (seed index, particle count, requested force)
};

class NeedleEventRing {
 public:
  explicit NeedleEventRing(int capacity = 4096) : buf_(static_cast<size_t>(capacity)) {}
  void push(const NeedleEvent& e) {  // no allocation
    buf_[head_] = e;
    head_ = (head_ + 1) % buf_.size();
    if (size_ < buf_.size()) ++size_;
    else ++dropped_;
    ++total_;
  }
  // Chronological copy (outside the step).
  std::vector<NeedleEvent> snapshot() const {
    std::vector<NeedleEvent> out;
    out.reserve(size_);
    const size_t first = (head_ + buf_.size() - size_) % buf_.size();
    for (size_t i = 0; i < size_; ++i) out.push_back(buf_[(first + i) % buf_.size()]);
    return out;
  }
  // Calls f(event) for every event pushed after the first `seen` ones that is still in the ring,
  // oldest first, and returns total(): readers outside the step (metrics) keep up without copying.
  template <class F>
  int64_t for_each_since(int64_t seen, F&& f) const {
    const int64_t oldest = total_ - static_cast<int64_t>(size_);
    const size_t first = (head_ + buf_.size() - size_) % buf_.size();
    for (int64_t k = seen > oldest ? seen : oldest; k < total_; ++k)
      f(buf_[(first + static_cast<size_t>(k - oldest)) % buf_.size()]);
    return total_;
  }
  // the i-th oldest event still held (0 <= i < size())
  const NeedleEvent& at(size_t i) const { return buf_[(head_ + buf_.size() - size_ + i) % buf_.size()]; }
  // save / restore / hash of the ring (engine/util/state_io.h), field by field (no padding)
  template <class IO>
  void serialize(IO& io) {
    for (NeedleEvent& e : buf_) {
      io.pod(e.kind);
      io.pod(e.needle);
      io.pod(e.time);
      io.vec(e.position);
      io.pod(e.depth);
      io.pod(e.force);
      io.pod(e.component);
      io.pod(e.node);
      io.pod(e.value);
    }
    io.pod(head_);
    io.pod(size_);
    io.pod(dropped_);
    io.pod(total_);
  }
  size_t size() const { return size_; }
  int64_t dropped() const { return dropped_; }
  int64_t total() const { return total_; }

 private:
  std::vector<NeedleEvent> buf_;
  size_t head_ = 0, size_ = 0;
  int64_t dropped_ = 0, total_ = 0;
};

}  // namespace ps
