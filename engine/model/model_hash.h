// Fingerprint of a compiled Model (the scenario editor's "same compiled scenario" check: a
// scenario saved and opened again must compile to the same hash). FNV-1a over the raw bytes of
// what the step reads: time settings, gravity, particles (rest positions, masses, stiffnesses,
// damping, components, tags), neighbourhoods and their weights, surfaces and constraints; the
// roles of components and tags only where `role:` differs from the name's default (a scene that
// names its organs hashes as before). The urethra line (Model::urethra) is left out: the step
// does not read it.
#pragma once
#include <cstdint>

#include "engine/model/model.h"

namespace ps {

uint64_t model_hash(const Model& m);

}  // namespace ps
