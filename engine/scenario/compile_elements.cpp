// Elements stage of compile_scenario (after the surfaces, which all use): each material model in
// use builds its elements (material_models.h: the strain model's clusters, the tet model's
// elements, the shell model's membranes, with what they change in the shape-memory term).
#include "engine/scenario/compile_stages.h"
#include "engine/scenario/material_models.h"

namespace ps {

void compile_elements(const ScenarioSpec& spec, Model& m, CompileWork& work) {
  for (const MaterialModelDesc* model : material_models())
    if (model->build && work.uses_model[static_cast<size_t>(model->model)]) model->build(spec, m, work);
  m.any_shape_memory = false;
  for (int p = 0, n = m.particle_count(); p < n; ++p) m.any_shape_memory |= (m.shape_memory[p] && m.k_e[p] > 0.0);
}

}  // namespace ps
