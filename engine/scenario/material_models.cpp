// The table of material models (material_models.h), in MaterialModel order.
#include "engine/scenario/material_models.h"

#include <array>

namespace ps {

namespace {
const std::array<const MaterialModelDesc*, kMaterialModelCount> kModels = {&kPaperMaterial, &kStrainMaterial, &kTetMaterial,
                                                                          &kShellMaterial};
}  // namespace

std::span<const MaterialModelDesc* const> material_models() { return kModels; }

const MaterialModelDesc& material_model(MaterialModel model) { return *kModels[static_cast<size_t>(model)]; }

const MaterialModelDesc* find_material_model(const std::string& name) {
  for (const MaterialModelDesc* d : kModels)
    if (name == d->name) return d;
  return nullptr;
}

double elastic_energy(const Model& m, const State& s) {
  double e = 0.0;
  for (const MaterialModelDesc* d : kModels)
    if (d->present(m)) e += d->energy(m, s);
  return e;
}

}  // namespace ps
