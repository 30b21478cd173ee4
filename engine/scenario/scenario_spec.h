// Moved to engine/spec/scenario_spec.h: tools/ and anatomy/ read the scenario description and
// sit below scenario/ (docs/architecture.md, the engine's layering). This forwarding header keeps
// code outside engine/ that names the old path building; engine/ code includes the new path.
#pragma once
#include "engine/spec/scenario_spec.h"
