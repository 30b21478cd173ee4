// Dosimetry validation (issue 46): `prostatesim validate tg43`.
#pragma once
#include <vector>

#include "app/checks/validation.h"

namespace ps::app {

std::vector<ValidationCase> dosimetry_validation_cases();   // validate_dosimetry.cpp

}  // namespace ps::app
