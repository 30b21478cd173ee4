#include "app/commands.h"

namespace ps::app {
void add_validate_command(CLI::App& app, Runner& run) {}
}  // namespace ps::app
