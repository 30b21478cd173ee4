// Needle validation cases (issue 4): `prostatesim validate needle`.
#pragma once
#include <vector>

#include "app/checks/validation.h"

namespace ps::app {

std::vector<ValidationCase> needle_validation_cases();   // validate_needle.cpp

}  // namespace ps::app
