// Hole labels of a brachytherapy template as clinical templates print them: columns in letters
// from the patient's right, capitals every 10 mm and the half-steps between them in lower case
// (A a B b C c D d E e F f G for 13 columns at 5 mm, D on the probe's midline), rows numbered from
// the probe up, whole numbers every 10 mm and half-steps between (1 1.5 2 ... 7 for 13 rows).
#pragma once
#include <optional>
#include <string>
#include <utility>

namespace ps::dosimetry {

std::string template_column_label(int col);
std::string template_row_label(int row);
inline std::string template_hole_label(int col, int row) { return template_column_label(col) + template_row_label(row); }
// "D3.5" -> (6, 5); nullopt when the text is not a hole label of a cols x rows template.
std::optional<std::pair<int, int>> parse_template_hole(const std::string& label, int cols, int rows);

}  // namespace ps::dosimetry
