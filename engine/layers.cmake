# The engine's layering: one static library per folder, listed bottom to top. A folder may include
# and link only the folders in its DEPS (and, through them, what those depend on); each DEPS entry
# must be listed before it. engine/CMakeLists.txt builds the targets from this table and
# tests/layering/check_layers.cmake (CTest engine_layering) checks every #include "engine/..."
# against it. docs/architecture.md draws it and says why each folder sits where it does.
set(PROSTATESIM_ENGINE_LAYERS
  util        # vectors, errors, atomic files, spatial grid, state I/O
  dosimetry   # TG-43U1 seed dose, dose grids, organ masks, DVH and indices, the implant plan
  draw        # DrawSink/DrawList: how a tool describes its geometry (header only)
  contract    # Command in, Snapshot/ToolReadout/SnapshotEvent out: plain data across threads
  mesh        # triangle meshes: import, check, simplify, query, OBJ
  model       # the immutable Model and what compile builds into it (coordinates, clusters, tets)
  state       # the State the step advances
  spec        # ScenarioSpec and the YAML reader: the parsed scenario, no behaviour
  anatomy     # pelvis shapes and prostate zones
  step        # Simulation, Tool interface and the physics stages
  tools       # needle, probe, filling, biopsy: the instruments (Tools) and their spec parsers
  ultrasound  # TRUS image from the tissue and the instruments
  metrics     # session metrics, tracked points, scores
  scenario    # YAML -> ScenarioSpec -> Model (compile_scenario and its stages), the editor document
  sim         # Scene (model + simulation + tools), run loop, trajectories, watchdog
  realtime    # physics thread, command queue, recording, scripts, triple buffer
  io          # output files, PNG
)
set(PROSTATESIM_ENGINE_DEPS_util)
set(PROSTATESIM_ENGINE_DEPS_dosimetry util)
set(PROSTATESIM_ENGINE_DEPS_draw util)
set(PROSTATESIM_ENGINE_DEPS_contract draw util)
set(PROSTATESIM_ENGINE_DEPS_mesh util)
set(PROSTATESIM_ENGINE_DEPS_model util)
set(PROSTATESIM_ENGINE_DEPS_state model)
set(PROSTATESIM_ENGINE_DEPS_spec util)
set(PROSTATESIM_ENGINE_DEPS_anatomy mesh model spec)
set(PROSTATESIM_ENGINE_DEPS_step contract draw model state)
set(PROSTATESIM_ENGINE_DEPS_tools anatomy mesh spec step)
set(PROSTATESIM_ENGINE_DEPS_metrics dosimetry spec tools)
set(PROSTATESIM_ENGINE_DEPS_scenario anatomy mesh metrics spec step tools)
set(PROSTATESIM_ENGINE_DEPS_sim scenario)
set(PROSTATESIM_ENGINE_DEPS_realtime sim)
set(PROSTATESIM_ENGINE_DEPS_ultrasound tools)
set(PROSTATESIM_ENGINE_DEPS_io sim)

# Folders this layer may include: itself and the transitive closure of its DEPS (sets <out>).
function(prostatesim_engine_reachable layer out)
  set(seen)
  set(todo ${PROSTATESIM_ENGINE_DEPS_${layer}})
  while(todo)
    list(POP_FRONT todo d)
    if(NOT d IN_LIST seen)
      list(APPEND seen ${d})
      list(APPEND todo ${PROSTATESIM_ENGINE_DEPS_${d}})
    endif()
  endwhile()
  set(${out} ${layer} ${seen} PARENT_SCOPE)
endfunction()
