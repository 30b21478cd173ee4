#include "engine/scenario/scenario_document.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "engine/metrics/tracked_point.h"
#include "engine/scenario/model_hash.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/tools/tool_kind.h"
#include "engine/util/atomic_file.h"
#include "engine/util/error.h"

namespace ps {

namespace {

struct PathToken {
  std::string key;
  bool has_selector = false;
  std::string selector;            // index digits or an item's name
};

std::vector<PathToken> split_path(const std::string& path) {
  std::vector<PathToken> out;
  size_t i = 0;
  while (i < path.size()) {
    PathToken t;
    while (i < path.size() && path[i] != '.' && path[i] != '[') t.key += path[i++];
    if (i < path.size() && path[i] == '[') {
      const size_t close = path.find(']', i);
      if (close == std::string::npos) throw InputError("", 0, path, "unclosed '[' in the key path");
      t.has_selector = true;
      t.selector = path.substr(i + 1, close - i - 1);
      i = close + 1;
    }
    if (t.key.empty()) throw InputError("", 0, path, "empty key in the key path");
    out.push_back(t);
    if (i < path.size() && path[i] == '.') ++i;
  }
  if (out.empty()) throw InputError("", 0, path, "empty key path");
  return out;
}

bool all_digits(const std::string& s) { return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; }); }

// End of a quoted scalar starting at pos (text[pos] is the quote).
size_t quoted_end(const std::string& t, size_t pos) {
  const char q = t[pos];
  for (size_t i = pos + 1; i < t.size(); ++i) {
    if (q == '"' && t[i] == '\\') { ++i; continue; }
    if (t[i] == q) {
      if (q == '\'' && i + 1 < t.size() && t[i + 1] == '\'') { ++i; continue; }
      return i + 1;
    }
  }
  return t.size();
}

// End of a flow collection starting at pos ('[' or '{').
size_t flow_end(const std::string& t, size_t pos) {
  int depth = 0;
  for (size_t i = pos; i < t.size(); ++i) {
    const char c = t[i];
    if (c == '"' || c == '\'') { i = quoted_end(t, i) - 1; continue; }
    if (c == '#' && i > 0 && (t[i - 1] == ' ' || t[i - 1] == '\t')) { while (i < t.size() && t[i] != '\n') ++i; continue; }
    if (c == '[' || c == '{') ++depth;
    if (c == ']' || c == '}') {
      if (--depth == 0) return i + 1;
    }
  }
  return t.size();
}

size_t plain_end(const std::string& t, size_t pos, bool in_flow) {
  size_t i = pos;
  for (; i < t.size(); ++i) {
    const char c = t[i];
    if (c == '\n' || c == '\r') break;
    if (c == '#' && i > pos && (t[i - 1] == ' ' || t[i - 1] == '\t')) break;
    if (in_flow && (c == ',' || c == ']' || c == '}')) break;
  }
  while (i > pos && (t[i - 1] == ' ' || t[i - 1] == '\t')) --i;
  return i;
}

size_t skip_anchor(const std::string& t, size_t pos) {
  if (pos < t.size() && t[pos] == '&') {
    while (pos < t.size() && t[pos] != ' ' && t[pos] != '\t' && t[pos] != '\n') ++pos;
    while (pos < t.size() && (t[pos] == ' ' || t[pos] == '\t')) ++pos;
  }
  return pos;
}

int line_at(const std::string& t, size_t pos) { return 1 + static_cast<int>(std::count(t.begin(), t.begin() + std::min(pos, t.size()), '\n')); }

YAML::Node load_yaml(const std::string& text) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError("", e.mark.line + 1, "", std::string("YAML: ") + e.msg);
  }
}

std::string number_text(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

// Segment p0-p1 against triangle abc (Moller-Trumbore): parameter t in [0, 1] of the crossing.
bool segment_hits_triangle(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b, const Vec3& c, double& t_out) {
  const Vec3 d = p1 - p0, e1 = b - a, e2 = c - a;
  const Vec3 h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-18) return false;
  const double inv = 1.0 / det;
  const Vec3 s = p0 - a;
  const double u = inv * s.dot(h);
  if (u < 0.0 || u > 1.0) return false;
  const Vec3 q = s.cross(e1);
  const double v = inv * d.dot(q);
  if (v < 0.0 || u + v > 1.0) return false;
  const double t = inv * e2.dot(q);
  if (t < 0.0 || t > 1.0) return false;
  t_out = t;
  return true;
}


// Bounding box of a bounded region (false for All / HalfSpace).
bool region_box(const RegionSpec& r, Vec3& lo, Vec3& hi) {
  switch (r.kind) {
    case RegionSpec::Box: lo = r.min; hi = r.max; return true;
    case RegionSpec::Sphere: lo = r.center - Vec3::Constant(r.radius); hi = r.center + Vec3::Constant(r.radius); return true;
    case RegionSpec::Ellipsoid: lo = r.center - r.radii; hi = r.center + r.radii; return true;
    default: return false;
  }
}

// The node at a key path (every key must exist); `seq_item` gets the index of the last token's
// selected item in its list (-1 without a selector).
struct Walked {
  YAML::Node node;                 // the value at the path
  YAML::Node list;                 // the list of the last selector (when it has one)
  int index = -1;
};

Walked walk_path(const YAML::Node& root, const std::vector<PathToken>& tokens) {
  Walked w;
  // (reset(), not '=': assigning a YAML::Node that refers to a node rewrites the node itself)
  YAML::Node cur;
  cur.reset(root);
  std::string walked;
  for (const PathToken& t : tokens) {
    walked += (walked.empty() ? "" : ".") + t.key;
    if (!cur.IsMap()) throw InputError("", 0, walked, "not inside a mapping");
    const YAML::Node child = cur[t.key];
    if (!child.IsDefined()) throw InputError("", 0, walked, "no such key");
    cur.reset(child);
    w.index = -1;
    if (t.has_selector) {
      if (!cur.IsSequence()) throw InputError("", 0, walked, "not a list");
      int found = -1;
      if (all_digits(t.selector)) {
        const size_t i = std::stoul(t.selector);
        if (i >= cur.size()) throw InputError("", 0, walked + "[" + t.selector + "]", "index beyond the list (" + std::to_string(cur.size()) + " items)");
        found = static_cast<int>(i);
      } else {
        for (size_t i = 0; i < cur.size() && found < 0; ++i)
          if (cur[i].IsMap() && cur[i]["name"] && cur[i]["name"].IsScalar() && cur[i]["name"].Scalar() == t.selector) found = static_cast<int>(i);
        if (found < 0) throw InputError("", 0, walked + "[" + t.selector + "]", "no item named '" + t.selector + "'");
      }
      walked += "[" + t.selector + "]";
      w.list.reset(cur);
      w.index = found;
      const YAML::Node item = w.list[static_cast<size_t>(found)];
      cur.reset(item);
    }
  }
  w.node.reset(cur);
  return w;
}

size_t line_begin(const std::string& t, size_t pos) {
  const size_t p = pos == 0 ? std::string::npos : t.rfind('\n', pos - 1);
  return p == std::string::npos ? 0 : p + 1;
}

// End of the text of a value starting at pos (scalar, quoted, flow collection).
size_t value_end(const std::string& t, size_t pos, bool in_flow) {
  if (t[pos] == '"' || t[pos] == '\'') return quoted_end(t, pos);
  if (t[pos] == '[' || t[pos] == '{') return flow_end(t, pos);
  return plain_end(t, pos, in_flow);
}

// A block list item's extent: from the start of its dash line to the end of its last content
// line (lines indented deeper than the dash; blank and comment lines in between included only
// when content follows them).
void block_item_extent(const std::string& t, size_t item_pos, size_t& begin, size_t& end, int& dash_col) {
  size_t dash = item_pos;
  while (dash > 0 && t[dash] != '-') --dash;
  begin = line_begin(t, dash);
  dash_col = static_cast<int>(dash - begin);
  end = t.find('\n', dash);
  if (end == std::string::npos) end = t.size();
  size_t ls = end;
  while (ls < t.size()) {
    const size_t b = ls + 1;
    size_t le = t.find('\n', b);
    if (le == std::string::npos) le = t.size();
    size_t ind = b;
    while (ind < le && t[ind] == ' ') ++ind;
    const bool blank = ind == le || t[ind] == '#' || t[ind] == '\r';
    if (!blank) {
      if (static_cast<int>(ind - b) <= dash_col) break;
      end = le;
    }
    ls = le;
  }
}

}  // namespace

ValueSpan locate_value(const std::string& text, const std::string& key_path) {
  const std::vector<PathToken> tokens = split_path(key_path);
  const YAML::Node root = load_yaml(text);
  YAML::Node cur;  // reset(), not '=': '=' on a YAML::Node rewrites the node it refers to
  cur.reset(root);
  bool in_flow = false;
  std::string walked;
  for (size_t k = 0; k < tokens.size(); ++k) {
    const PathToken& t = tokens[k];
    walked += (walked.empty() ? "" : ".") + t.key;
    if (!cur.IsMap()) throw InputError("", 0, walked, "not inside a mapping");
    if (cur.Style() == YAML::EmitterStyle::Flow) in_flow = true;
    const YAML::Node child = cur[t.key];
    const bool last = k + 1 == tokens.size();
    if (!child.IsDefined() && last && !t.has_selector) {
      // missing key: add it to this mapping
      ValueSpan s;
      s.exists = false;
      size_t pos = skip_anchor(text, cur.Mark().pos);
      if (cur.Style() == YAML::EmitterStyle::Flow || (pos < text.size() && text[pos] == '{')) {
        size_t close = flow_end(text, pos) - 1;  // the '}'
        size_t ins = close;
        while (ins > pos + 1 && (text[ins - 1] == ' ' || text[ins - 1] == '\t')) --ins;
        s.begin = s.end = ins;
        s.insert_prefix = cur.size() > 0 ? ", " : "";
        return s;
      }
      if (cur.size() == 0) throw InputError("", 0, walked, "cannot add a key to an empty block mapping");
      const YAML::Mark first = cur.begin()->first.Mark();
      const int col = first.column;
      // the mapping ends before the first later line indented less than its keys
      size_t line_start = text.find('\n', first.pos);
      size_t last_content_end = text.find('\n', first.pos);
      if (last_content_end == std::string::npos) last_content_end = text.size();
      while (line_start != std::string::npos && line_start + 1 < text.size()) {
        const size_t ls = line_start + 1;
        size_t le = text.find('\n', ls);
        if (le == std::string::npos) le = text.size();
        size_t ind = ls;
        while (ind < le && text[ind] == ' ') ++ind;
        const bool blank = ind == le || text[ind] == '#' || text[ind] == '\r';
        if (!blank) {
          if (static_cast<int>(ind - ls) < col) break;
          last_content_end = le;
        }
        line_start = le < text.size() ? le : std::string::npos;
      }
      s.begin = s.end = last_content_end;
      s.insert_prefix = "\n" + std::string(static_cast<size_t>(col), ' ');
      return s;
    }
    if (!child.IsDefined()) throw InputError("", 0, walked, "no such key");
    // an alias (*name) shares the anchored node, whose mark points at the anchor: an edit through
    // it would silently change every user of the anchor, so it is refused
    for (auto it = cur.begin(); it != cur.end(); ++it) {
      if (!it->first.IsScalar() || it->first.Scalar() != t.key) continue;
      size_t p = it->first.Mark().pos;
      if (p < text.size() && (text[p] == '"' || text[p] == '\'')) p = quoted_end(text, p);
      while (p < text.size() && text[p] != ':') ++p;
      ++p;
      while (p < text.size() && (text[p] == ' ' || text[p] == '\t')) ++p;
      if (p < text.size() && text[p] == '*')
        throw InputError("", line_at(text, p), walked,
                         "the value is an alias (" + text.substr(p, text.find_first_of(",}] \n", p) - p) + "): edit the anchored value");
      break;
    }
    cur.reset(child);
    if (t.has_selector) {
      if (!cur.IsSequence()) throw InputError("", 0, walked, "not a list");
      if (cur.Style() == YAML::EmitterStyle::Flow) in_flow = true;
      YAML::Node item;
      if (all_digits(t.selector)) {
        const size_t i = std::stoul(t.selector);
        if (i >= cur.size()) throw InputError("", 0, walked + "[" + t.selector + "]", "index beyond the list (" + std::to_string(cur.size()) + " items)");
        item = cur[i];
      } else {
        for (size_t i = 0; i < cur.size(); ++i)
          if (cur[i].IsMap() && cur[i]["name"] && cur[i]["name"].IsScalar() && cur[i]["name"].Scalar() == t.selector) { item = cur[i]; break; }
        if (!item.IsDefined()) throw InputError("", 0, walked + "[" + t.selector + "]", "no item named '" + t.selector + "'");
      }
      walked += "[" + t.selector + "]";
      cur.reset(item);
    }
  }
  ValueSpan s;
  s.exists = true;
  size_t pos = skip_anchor(text, cur.Mark().pos);
  if (pos >= text.size()) throw InputError("", 0, key_path, "value not found in the text");
  if (text[pos] == '*') throw InputError("", line_at(text, pos), key_path, "the value is an alias (" + text.substr(pos, text.find_first_of(",}] \n", pos) - pos) + "): edit the anchored value");
  s.begin = pos;
  if (text[pos] == '"' || text[pos] == '\'') s.end = quoted_end(text, pos);
  else if (text[pos] == '[' || text[pos] == '{') s.end = flow_end(text, pos);
  else if (cur.IsScalar()) s.end = plain_end(text, pos, in_flow);
  else throw InputError("", line_at(text, pos), key_path, "a block list or mapping: edit its items");
  return s;
}

std::optional<DocumentIssue> check_scenario_semantics(const ScenarioSpec& spec, const Model& m) {
  // needle targets inside an organ
  for (const NeedleSpec& n : spec.needles.needles)
    if (n.target && component_holding(m, *n.target) < 0)
      return DocumentIssue{n.key + ".target_mm", n.line, "the target lies outside every organ"};
  // lesions that overlap: shared particles, or shared volume of bounded regions (0.5 mm grid)
  for (size_t a = 0; a < spec.tags.size(); ++a) {
    if (m.tag_role(m.find_tag(spec.tags[a].name)) != Role::Lesion) continue;
    for (size_t b = a + 1; b < spec.tags.size(); ++b) {
      if (m.tag_role(m.find_tag(spec.tags[b].name)) != Role::Lesion) continue;
      const int ta = m.find_tag(spec.tags[a].name), tb = m.find_tag(spec.tags[b].name);
      int shared = 0;
      if (ta >= 0 && tb >= 0 && !m.particle_tags.empty())
        for (uint64_t bits : m.particle_tags) shared += (bits >> ta & 1u) && (bits >> tb & 1u);
      bool volume = false;
      Vec3 lo, hi;
      if (region_box(spec.tags[b].region, lo, hi)) {
        const double h = 0.5e-3;
        for (double x = lo.x(); x <= hi.x() && !volume; x += h)
          for (double y = lo.y(); y <= hi.y() && !volume; y += h)
            for (double z = lo.z(); z <= hi.z() && !volume; z += h) {
              const Vec3 p(x, y, z);
              volume = spec.tags[a].region.contains(p) && spec.tags[b].region.contains(p);
            }
      }
      if (shared > 0 || volume)
        return DocumentIssue{"tags[" + std::to_string(b) + "].region", spec.tags[b].loc.line,
                             "lesion '" + spec.tags[b].name + "' overlaps lesion '" + spec.tags[a].name + "'" +
                                 (shared > 0 ? " (" + std::to_string(shared) + " particles in both)" : "")};
    }
  }
  // needle paths through bone
  for (const NeedleSpec& n : spec.needles.needles) {
    double depth = 0.0;
    for (const NeedleScriptPoint& q : n.script) depth = std::max(depth, q.depth);
    if (n.gun) depth += n.gun->stroke;
    const Vec3 dir = n.direction.normalized();
    if (n.target) depth = std::max(depth, (*n.target - n.start).dot(dir));
    if (depth <= 0.0) continue;
    const Vec3 p0 = n.start, p1 = n.start + depth * dir;
    for (const Component& c : m.components) {
      if (c.kind != ComponentKind::Rigid || c.surface < 0) continue;
      double best = INFINITY;
      for (const auto& f : m.surfaces[c.surface].faces) {
        double t = 0.0;
        if (segment_hits_triangle(p0, p1, m.rest_pos[f[0]], m.rest_pos[f[1]], m.rest_pos[f[2]], t)) best = std::min(best, t);
      }
      if (std::isfinite(best))
        return DocumentIssue{n.key + (n.script.empty() ? ".direction" : ".script"), n.line,
                             "the planned path of needle '" + n.name + "' goes through bone '" + c.name + "' at " +
                                 number_text(std::round(1e4 * best * depth) / 10.0) + " mm"};
    }
  }
  return std::nullopt;
}

ScenarioDocument ScenarioDocument::open(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot be read");
  std::stringstream ss;
  ss << in.rdbuf();
  ScenarioDocument d(ss.str(), path);
  return d;
}

ScenarioDocument::ScenarioDocument(std::string text, std::string path) : path_(std::move(path)) {
  load(text);
  saved_text_ = text_;
  history_.push_back(text_);
}

namespace {
struct Compiled {
  std::unique_ptr<ScenarioSpec> spec;
  std::shared_ptr<const Model> model;
  std::optional<DocumentIssue> issue;
};

Compiled compile_text(const std::string& text, const std::string& path) {
  Compiled c;
  try {
    c.spec = std::make_unique<ScenarioSpec>(parse_scenario_text(text, path));
    c.model = compile_scenario(*c.spec);
    // each instrument checks its spec against the model (the needle's paths, the probe's start pose
    // in the rectum and not in bone, the filling's volume-constrained organ and volumes in range)
    for (const ToolKind* k : tool_kinds()) k->make(*c.spec, c.model);
    c.issue = check_scenario_semantics(*c.spec, *c.model);
  } catch (const InputError& e) {
    c.issue = DocumentIssue{e.field(), e.line(), e.message()};
  } catch (const CompileError& e) {
    c.issue = DocumentIssue{"", 0, e.what()};
  } catch (const std::exception& e) {
    c.issue = DocumentIssue{"", 0, e.what()};
  }
  if (c.issue) {  // an invalid scenario has no spec or model to show
    c.spec.reset();
    c.model.reset();
  }
  return c;
}
}  // namespace

void ScenarioDocument::load(const std::string& text) {
  text_ = text;
  Compiled c = compile_text(text, path_);
  spec_ = std::move(c.spec);
  model_ = c.model;
  issue_ = c.issue;
  hash_ = model_ ? ps::model_hash(*model_) : 0;
}

EditResult ScenarioDocument::set(const std::string& key_path, const std::string& yaml_value) {
  EditResult r;
  ValueSpan span;
  try {
    span = locate_value(text_, key_path);
  } catch (const InputError& e) {
    r.issue = DocumentIssue{e.field().empty() ? key_path : e.field(), e.line(), e.message()};
    return r;
  }
  std::string next = text_;
  if (span.exists) {
    next.replace(span.begin, span.end - span.begin, yaml_value);
  } else {
    const std::string key = key_path.substr(key_path.find_last_of('.') == std::string::npos ? 0 : key_path.find_last_of('.') + 1);
    next.insert(span.begin, span.insert_prefix + key + ": " + yaml_value + span.insert_suffix);
  }
  Compiled c = compile_text(next, path_);
  if (c.issue && !issue_) {  // a valid document stays valid
    r.issue = c.issue;
    if (r.issue->field.empty()) r.issue->field = key_path;
    return r;
  }
  // an invalid document (opened so) accepts edits that parse, so its errors can be fixed one by one
  text_ = next;
  spec_ = std::move(c.spec);
  model_ = c.model;
  issue_ = c.issue;
  hash_ = model_ ? ps::model_hash(*model_) : 0;
  history_.resize(at_ + 1);
  history_.push_back(text_);
  ++at_;
  r.ok = true;
  return r;
}

std::string text_with_item_added(const std::string& text, const std::string& list_path, const std::string& item) {
  const std::vector<PathToken> tokens = split_path(list_path);
  if (tokens.back().has_selector) throw InputError("", 0, list_path, "name the list, not one of its items");
  const YAML::Node root = load_yaml(text);
  const Walked w = walk_path(root, tokens);
  const YAML::Node& list = w.node;
  if (!list.IsSequence()) throw InputError("", 0, list_path, "not a list");
  std::string next = text;
  const size_t pos = skip_anchor(text, list.Mark().pos);
  if (pos < text.size() && text[pos] == '*') throw InputError("", line_at(text, pos), list_path, "the list is an alias: edit the anchored list");
  if (list.Style() == YAML::EmitterStyle::Flow || (pos < text.size() && text[pos] == '[')) {
    size_t close = flow_end(text, pos) - 1;  // the ']'
    size_t ins = close;
    while (ins > pos + 1 && (text[ins - 1] == ' ' || text[ins - 1] == '\t' || text[ins - 1] == '\n')) --ins;
    next.insert(ins, (list.size() > 0 ? ", " : "") + item);
    return next;
  }
  if (list.size() == 0) throw InputError("", line_at(text, pos), list_path, "an empty block list");
  size_t b = 0, e = 0;
  int col = 0;
  block_item_extent(text, skip_anchor(text, list[list.size() - 1].Mark().pos), b, e, col);
  next.insert(e, "\n" + std::string(static_cast<size_t>(col), ' ') + "- " + item);
  return next;
}

std::string text_with_item_removed(const std::string& text, const std::string& item_path) {
  const std::vector<PathToken> tokens = split_path(item_path);
  if (!tokens.back().has_selector) throw InputError("", 0, item_path, "name an item of a list ([index] or [name])");
  const YAML::Node root = load_yaml(text);
  const Walked w = walk_path(root, tokens);
  const YAML::Node& list = w.list;
  const size_t n = list.size(), i = static_cast<size_t>(w.index);
  const size_t lpos = skip_anchor(text, list.Mark().pos);
  std::string next = text;
  auto item_begin = [&](size_t k) { return skip_anchor(text, list[k].Mark().pos); };
  if (list.Style() == YAML::EmitterStyle::Flow || (lpos < text.size() && text[lpos] == '[')) {
    size_t b = item_begin(i), e = value_end(text, b, true);
    if (i + 1 < n) e = item_begin(i + 1);                       // "item, " up to the next item
    else if (i > 0) b = value_end(text, item_begin(i - 1), true);  // ", item" after the previous
    next.erase(b, e - b);
    return next;
  }
  size_t b = 0, e = 0;
  int col = 0;
  block_item_extent(text, item_begin(i), b, e, col);
  if (n == 1) {
    // the list's only item: its key keeps an empty flow list (and a comment on the key's line)
    size_t k = b;
    while (k > 0) {  // back over blank and comment lines to the key's line
      const size_t ls = line_begin(text, k - 1);
      size_t ind = ls;
      while (ind < text.size() && text[ind] == ' ') ++ind;
      if (ind < text.size() && (text[ind] == '#' || text[ind] == '\n')) { k = ls; continue; }
      break;
    }
    if (k == 0) throw InputError("", line_at(text, b), item_path, "cannot find the list's key");
    const size_t key_line = line_begin(text, k - 1), key_end = k - 1;
    size_t c = key_line;
    while (c < key_end && text[c] != ':') {
      if (text[c] == '"' || text[c] == '\'') c = quoted_end(text, c) - 1;
      ++c;
    }
    if (c >= key_end) throw InputError("", line_at(text, b), item_path, "cannot find the list's key");
    size_t comment = text.find(" #", c + 1);
    if (comment == std::string::npos || comment > key_end) comment = key_end;
    return text.substr(0, c + 1) + " []" + text.substr(comment, key_end - comment) + text.substr(e);
  }
  // the item's lines and their newline
  if (e < next.size() && next[e] == '\n') ++e;
  else if (b > 0) --b;  // the last line of the file: take the newline before it
  next.erase(b, e - b);
  return next;
}

EditResult ScenarioDocument::accept(std::string next, const std::string& field) {
  EditResult r;
  Compiled c = compile_text(next, path_);
  if (c.issue && !issue_) {
    r.issue = c.issue;
    if (r.issue->field.empty()) r.issue->field = field;
    return r;
  }
  text_ = std::move(next);
  spec_ = std::move(c.spec);
  model_ = c.model;
  issue_ = c.issue;
  hash_ = model_ ? ps::model_hash(*model_) : 0;
  history_.resize(at_ + 1);
  history_.push_back(text_);
  ++at_;
  r.ok = true;
  return r;
}

EditResult ScenarioDocument::add_item(const std::string& list_path, const std::string& yaml_item) {
  std::string next;
  try {
    const std::vector<PathToken> tokens = split_path(list_path);
    bool missing = false;
    try {
      walk_path(load_yaml(text_), tokens);
    } catch (const InputError& e) {
      missing = e.field() == list_path && std::string(e.what()).find("no such key") != std::string::npos;
      if (!missing) throw;
    }
    if (missing) return set(list_path, "[" + yaml_item + "]");
    next = text_with_item_added(text_, list_path, yaml_item);
  } catch (const InputError& e) {
    EditResult r;
    r.issue = DocumentIssue{e.field().empty() ? list_path : e.field(), e.line(), e.message()};
    return r;
  }
  return accept(std::move(next), list_path);
}

EditResult ScenarioDocument::remove_item(const std::string& item_path) {
  std::string next;
  try {
    next = text_with_item_removed(text_, item_path);
  } catch (const InputError& e) {
    EditResult r;
    r.issue = DocumentIssue{e.field().empty() ? item_path : e.field(), e.line(), e.message()};
    return r;
  }
  return accept(std::move(next), item_path);
}

EditResult ScenarioDocument::remove_top_key(const std::string& key) {
  size_t b = std::string::npos;
  for (size_t pos = 0; pos < text_.size();) {
    if (text_.compare(pos, key.size() + 1, key + ":") == 0) { b = pos; break; }
    const size_t nl = text_.find('\n', pos);
    pos = nl == std::string::npos ? text_.size() : nl + 1;
  }
  if (b == std::string::npos) {
    EditResult r;
    r.issue = DocumentIssue{key, 0, "no top-level key '" + key + "'"};
    return r;
  }
  auto line_end = [&](size_t p) {
    const size_t nl = text_.find('\n', p);
    return nl == std::string::npos ? text_.size() : nl + 1;
  };
  size_t e = line_end(b);
  for (size_t p = e; p < text_.size();) {
    const size_t next = line_end(p);
    const char c = text_[p];
    if (c == ' ' || c == '\t' || c == '-') e = next;                  // its block value
    else if (!(c == '\n' || c == '\r' || c == '#')) break;           // the next key
    p = next;                                                          // blank or comment: look on
  }
  std::string next = text_;
  next.erase(b, e - b);
  return accept(std::move(next), key);
}

bool ScenarioDocument::merge_last(int n) {
  if (n < 1 || at_ < static_cast<size_t>(n) || at_ + 1 != history_.size()) return false;
  history_.erase(history_.end() - n, history_.end() - 1);
  at_ -= static_cast<size_t>(n - 1);
  return true;
}

int ScenarioDocument::item_count(const std::string& list_path) const {
  try {
    const YAML::Node root = load_yaml(text_);
    const Walked w = walk_path(root, split_path(list_path));
    return w.node.IsSequence() ? static_cast<int>(w.node.size()) : 0;
  } catch (const std::exception&) {
    return 0;
  }
}

EditResult ScenarioDocument::set_number(const std::string& key_path, double v) { return set(key_path, number_text(v)); }

EditResult ScenarioDocument::set_vec3(const std::string& key_path, const Vec3& v) {
  return set(key_path, "[" + number_text(v.x()) + ", " + number_text(v.y()) + ", " + number_text(v.z()) + "]");
}

std::string ScenarioDocument::value_text(const std::string& key_path) const {
  try {
    const ValueSpan s = locate_value(text_, key_path);
    return s.exists ? text_.substr(s.begin, s.end - s.begin) : std::string();
  } catch (const InputError&) {
    return {};
  }
}

bool ScenarioDocument::undo() {
  if (!can_undo()) return false;
  load(history_[--at_]);
  return true;
}

bool ScenarioDocument::redo() {
  if (!can_redo()) return false;
  load(history_[++at_]);
  return true;
}

void ScenarioDocument::save(const std::string& path) {
  const std::string p = path.empty() ? path_ : path;
  if (issue_) throw InputError(p, issue_->line, issue_->field, "not saved: the scenario is invalid: " + issue_->message);
  write_file_atomic(p, text_);
  saved_text_ = text_;
}

}  // namespace ps
