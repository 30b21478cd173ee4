// Fingerprint of a compiled Model (the scenario editor's "same compiled scenario" check: a
// scenario saved and opened again must compile to the same hash). FNV-1a over the raw bytes of
// what the step reads: time settings, gravity, particles (rest positions, masses, stiffnesses,
// damping, components, tags), neighbourhoods and their weights, surfaces and constraints; the
// roles of components and tags only where `role:` differs from the name's default (a scene that
// names its organs hashes the same with or without `role:`). The urethra line (Model::urethra) is left out: the step
// does not read it.
//
// Each material model hashes its own elements (MaterialModelDesc::hash, engine/scenario/
// material_models.h), in MaterialModel order, after the surfaces.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "engine/model/model.h"

namespace ps {

// FNV-1a 64 over raw bytes; what model_hash and the material models' hash hooks feed.
class ModelHasher {
 public:
  void bytes(const void* p, size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (size_t i = 0; i < n; ++i) {
      h_ ^= b[i];
      h_ *= 1099511628211ull;
    }
  }
  template <class T>
  void pod(const T& v) {
    bytes(&v, sizeof v);
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    pod(v.size());
    if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
  }
  void str(const std::string& s) {
    pod(s.size());
    bytes(s.data(), s.size());
  }
  uint64_t value() const { return h_; }

 private:
  uint64_t h_ = 1469598103934665603ull;
};

uint64_t model_hash(const Model& m);

}  // namespace ps
