// One routine per tool walks its mutable state; the same walk saves it, restores it and hashes
// it (a tool that adds a field adds it once, to serialize(), and all three follow). Buffers that
// are sized at construction are walked by content only: a restore into a tool built from the same
// scene has the same sizes, and a mismatch throws instead of reading past the end.
// Saving and hashing run between ticks (never inside Simulation::step).
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "engine/util/vec.h"

namespace ps {

class StateIO {
 public:
  enum Mode : uint8_t { Save, Restore };
  // Save: buf is overwritten from its start; it holds exactly the saved bytes after finish() or
  // the destructor (until then it may be longer). Its capacity is reused: a buffer that held a
  // save of the same simulation takes the next one without allocating.
  explicit StateIO(std::vector<uint8_t>& buf, Mode mode) : buf_(buf), mode_(mode) {
    if (mode == Save) buf_.resize(buf_.capacity());  // written at pos_ with memcpy (no insert per field)
  }
  ~StateIO() { finish(); }
  StateIO(const StateIO&) = delete;
  StateIO& operator=(const StateIO&) = delete;
  // Save: cuts buf to the bytes written. Idempotent.
  void finish() {
    if (mode_ == Save) buf_.resize(pos_);
  }
  bool saving() const { return mode_ == Save; }
  size_t position() const { return pos_; }

  // raw bytes of a trivially copyable value
  template <class T>
  void pod(T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&v, sizeof(T));
  }
  void bytes(void* p, size_t n) {
    uint8_t* s = span(n);
    if (!n) return;
    if (mode_ == Save) std::memcpy(s, p, n);
    else std::memcpy(p, s, n);
  }
  // The next n bytes, to be filled (Save) or read (Restore) by the caller: for a long run of
  // small fields (a needle's anchors), copied at fixed offsets from one pointer instead of one
  // bytes() call each, whose bounds check and position update the compiler cannot hoist (a byte
  // store may alias the buffer's own pointers). The same bytes as the fields' bytes() calls.
  uint8_t* span(size_t n) {
    if (mode_ == Save) {
      // grown geometrically: the state has thousands of small fields (a needle's anchors), and
      // one vector insert each cost about a tenth of a brachytherapy tick in a per-tick save
      if (pos_ + n > buf_.size()) buf_.resize(std::max(pos_ + n, 2 * buf_.size()));
    } else if (pos_ + n > buf_.size()) {
      throw std::runtime_error("StateIO: saved state is shorter than this simulation's");
    }
    uint8_t* p = buf_.data() + pos_;
    pos_ += n;
    return p;
  }
  void vec(Vec3& v) { bytes(v.data(), 3 * sizeof(double)); }
  void quat(Quat& q) { bytes(q.coeffs().data(), 4 * sizeof(double)); }
  // a vector of trivially copyable values: its length is part of the state (checked on restore
  // when fixed, resized when `resizable`: only outside the step, e.g. a core's particle list)
  template <class T>
  void array(std::vector<T>& v, bool resizable = false) {
    uint64_t n = v.size();
    pod(n);
    if (mode_ == Restore && n != v.size()) {
      if (!resizable) throw std::runtime_error("StateIO: buffer size differs from the saved state's");
      v.resize(n);
    }
    // Vec3 and Quat are plain doubles without padding: the whole array is one copy, the same
    // bytes as one vec() / quat() per element (per element, the app's per-tick save of the last
    // good state cost about a quarter of a tick)
    if constexpr (std::is_same_v<T, Vec3>) {
      static_assert(sizeof(Vec3) == 3 * sizeof(double));
      if (n) bytes(v.data()->data(), n * sizeof(Vec3));
    } else if constexpr (std::is_same_v<T, Quat>) {
      static_assert(sizeof(Quat) == 4 * sizeof(double));
      if (n) bytes(v.data()->coeffs().data(), n * sizeof(Quat));
    } else {
      static_assert(std::is_trivially_copyable_v<T>);
      if (n) bytes(v.data(), n * sizeof(T));
    }
  }
  void string(std::string& s) {
    uint64_t n = s.size();
    pod(n);
    if (mode_ == Restore) s.resize(n);
    if (n) bytes(s.data(), n);
  }
  void strings(std::vector<std::string>& v) {
    uint64_t n = v.size();
    pod(n);
    if (mode_ == Restore) v.resize(n);
    for (auto& s : v) string(s);
  }

 private:
  std::vector<uint8_t>& buf_;
  Mode mode_;
  size_t pos_ = 0;
};

// FNV-1a 64 over bytes (the same as hash_state).
inline uint64_t fnv1a(const void* p, size_t n, uint64_t h = 1469598103934665603ull) {
  const auto* b = static_cast<const uint8_t*>(p);
  for (size_t i = 0; i < n; ++i) {
    h ^= b[i];
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace ps
