// The physics stopped on a NaN, blow-up or tunnelling check (State::fault) while a command ran a
// case to completion: not bad input and not a bug, the scene is numerically out of its range.
// The message names the particle and the time. `prostatesim` maps it to exit 3.
#pragma once
#include <stdexcept>

namespace ps {

class SimulationFault : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ps
