// Fixture of the frontend_layering_catches_upward test: render/ sits below the trainee window, so
// including app/gui/ from it is the kind of upward include the check must refuse. Not compiled.
#pragma once
#include "app/gui/trainee_window.h"
