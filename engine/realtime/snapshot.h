// Moved to engine/contract/snapshot.h: the step's Tool interface (engine/step/simulation.h) uses it,
// and step/ sits below realtime/ (docs/architecture.md, the engine's layering). This forwarding
// header keeps code outside engine/ that names the old path building; engine/ code includes
// the new path.
#pragma once
#include "engine/contract/snapshot.h"
