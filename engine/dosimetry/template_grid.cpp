#include "engine/dosimetry/template_grid.h"

namespace ps::dosimetry {

std::string template_column_label(int col) {
  const char c = static_cast<char>((col % 2 == 0 ? 'A' : 'a') + col / 2);
  return std::string(1, c);
}

std::string template_row_label(int row) {
  return std::to_string(1 + row / 2) + (row % 2 ? ".5" : "");
}

std::optional<std::pair<int, int>> parse_template_hole(const std::string& label, int cols, int rows) {
  if (label.size() < 2) return std::nullopt;
  const char c = label[0];
  int col = -1;
  if (c >= 'A' && c <= 'Z') col = 2 * (c - 'A');
  else if (c >= 'a' && c <= 'z') col = 2 * (c - 'a') + 1;
  if (col < 0 || col >= cols) return std::nullopt;
  for (int row = 0; row < rows; ++row)
    if (label.substr(1) == template_row_label(row)) return std::make_pair(col, row);
  return std::nullopt;
}

}  // namespace ps::dosimetry
