// Errors raised while reading user input (scenario, mesh, script) or while simulating.
// An InputError always names where the problem is: file, line (1-based, 0 if unknown) and field.
#pragma once
#include <stdexcept>
#include <string>

namespace ps {

class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, std::string field, const std::string& message)
      : std::runtime_error(format(file, line, field, message)),
        file_(std::move(file)), line_(line), field_(std::move(field)), message_(message) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& field() const { return field_; }
  // the reason alone, without the "file:line: 'field': " that what() puts in front (for callers
  // that carry the location beside it, as the scenario editor does)
  const std::string& message() const { return message_; }

 private:
  static std::string format(const std::string& file, int line, const std::string& field,
                            const std::string& message) {
    std::string s = file.empty() ? std::string("<input>") : file;
    if (line > 0) s += ":" + std::to_string(line);
    s += ": ";
    if (!field.empty()) s += "'" + field + "': ";
    return s + message;
  }
  std::string file_;
  int line_;
  std::string field_;
  std::string message_;
};

// A model that cannot be compiled (degenerate neighbourhood, bad surface): names the particle/face.
class CompileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ps
