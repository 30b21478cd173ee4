// What the kinds' timeline parsers share (engine/tools/tool_kind.h, ToolAction::parse).
#pragma once
#include <string>

#include "engine/spec/yaml_reader.h"

namespace ps {

// An entry's instrument or organ name (its action's value, `{fire: biopsy_1}`); InputError naming
// `key` when it is not a plain name.
inline std::string timeline_target(const YamlReader& r, const YAML::Node& value, const std::string& key) {
  if (!value.IsScalar()) r.fail(value, key, "expected an instrument name");
  return value.Scalar();
}

}  // namespace ps
