// A one-line progress bar on stderr for long commands (stress, bench, validate). Drawn only when
// stderr is a terminal, so logs, pipes and the tests see nothing of it.
#pragma once
#include <chrono>
#include <string>

namespace ps::app {

class Progress {
 public:
  // total: number of units of work (cases, runs); label: the command name.
  Progress(std::string label, int total);
  ~Progress();  // clears the line
  // Sets the units done and the item being worked on; redraws at most 10 times a second.
  void update(int done, const std::string& item);
  // Redraw now (item finished) and move on.
  void step(const std::string& item) { update(++done_, item); }
  // Erases the bar (before printing a table row to the same terminal); the next update redraws.
  void clear();
  bool enabled() const { return enabled_; }

 private:
  void draw();
  std::string label_, item_;
  int total_, done_ = 0;
  bool enabled_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace ps::app
