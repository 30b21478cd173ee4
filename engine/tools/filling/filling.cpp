#include "engine/tools/filling/filling.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "engine/util/error.h"

namespace ps {

namespace {

constexpr double kMl = 1e-6;  // ml -> m^3

std::string fmt(const char* f, double a, double b = 0.0, double c = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

}  // namespace

FillingTool::FillingTool(const FillingSpec& spec, const Model& m) : max_rate_(spec.max_rate), file_(spec.loc.file) {
  if (!(max_rate_ > 0.0) || !std::isfinite(max_rate_))
    throw InputError(file_, spec.loc.line, "filling.max_rate_ml_s", "must be a positive number");
  for (size_t i = 0; i < spec.schedule.size(); ++i) {
    const FillSpec& f = spec.schedule[i];
    const std::string key = "filling.schedule[" + std::to_string(i) + "]";
    const int c = m.find_component(f.component);
    if (c < 0) throw InputError(file_, f.loc.line, key + ".component", "unknown component '" + f.component + "'");
    const int si = m.components[c].surface;
    if (si < 0 || !m.surfaces[si].volume_constrained)
      throw InputError(file_, f.loc.line, key + ".component",
                       "'" + f.component + "' has no volume constraint: give its material incompressible: true so the "
                       "volume projection holds the filling target");
    if (!std::isfinite(f.value) || !std::isfinite(f.t0) || !std::isfinite(f.t1) || f.t1 < f.t0)
      throw InputError(file_, f.loc.line, key, "non-finite value or ramp end before its start");
    if (f.kind != FillSpec::Rate && !(f.value > 0.0))
      throw InputError(file_, f.loc.line, key + (f.kind == FillSpec::Target ? ".target_ml" : ".target_factor"),
                       "a target volume must be > 0");
    auto it = std::find_if(organs_.begin(), organs_.end(), [&](const Organ& o) { return o.surface == si; });
    if (it == organs_.end()) {
      Organ o;
      o.surface = si;
      o.name = f.component;
      o.rest = m.surfaces[si].rest_volume;
      o.base = o.rest;
      o.current = o.rest;
      organs_.push_back(std::move(o));
      it = organs_.end() - 1;
    }
    Raw r;
    r.kind = f.kind == FillSpec::Rate ? FillSpec::Rate : FillSpec::Target;
    r.value = f.kind == FillSpec::Factor ? f.value * it->rest : f.value;
    r.t0 = f.t0;
    r.t1 = f.t1;
    r.entry = static_cast<int>(i);
    r.line = f.loc.line;
    r.live = false;
    it->raw.push_back(r);
  }
  for (Organ& o : organs_) {
    std::stable_sort(o.raw.begin(), o.raw.end(), [](const Raw& a, const Raw& b) { return a.t0 < b.t0; });
    resolve(o, true);
    // room for live commands: applying one between ticks does not allocate (issue 10), up to
    // kLiveSegments of them per organ
    o.slots = o.raw.size() + kLiveSegments;
    o.raw.reserve(o.slots);
    o.seg.reserve(o.slots);
  }
}

// Between ticks on the physics thread for a live command: a plain record, no text (tool_reports.h).
void FillingTool::report(const Organ& o, const Raw& r, ToolReportCode code, double a, double b, double c) {
  ToolReport rep;
  rep.code = code;
  rep.live = r.live ? 1 : 0;
  rep.organ = static_cast<int16_t>(&o - organs_.data());
  rep.line = r.line;
  rep.entry = r.entry;
  rep.time = r.t0;
  rep.a = a;
  rep.b = b;
  rep.c = c;
  reports_.push(rep);
}

void FillingTool::resolve(Organ& o, bool constructing) {
  const double lo = kMinVolumeFraction * o.rest, hi = kMaxVolumeFactor * o.rest;
  auto field = [&](const Raw& r) { return "filling.schedule[" + std::to_string(r.entry) + "]"; };  // errors only
  o.seg.clear();
  for (Raw& r : o.raw) {
    double v0 = o.base;
    if (!o.seg.empty()) {
      Segment& prev = o.seg.back();
      prev.t1 = std::min(prev.t1, r.t0);  // the later segment takes over
      v0 = prev.v0 + prev.slope * (prev.t1 - prev.t0);
    }
    Segment s{r.t0, r.t1, v0, 0.0};
    if (r.kind == FillSpec::Rate) {
      if (std::abs(r.value) > max_rate_) {
        report(o, r, ToolReportCode::FillRateClamped, r.value, max_rate_, std::copysign(max_rate_, r.value));
        r.value = std::copysign(max_rate_, r.value);
      }
      s.slope = r.value;
      const double v_end = v0 + r.value * (r.t1 - r.t0);
      if (r.value != 0.0 && (v_end < lo * (1 - 1e-12) || v_end > hi * (1 + 1e-12))) {
        const double bound = v_end < lo ? lo : hi;
        if (constructing && !r.live)
          throw InputError(file_, r.line, field(r) + ".rate_ml_s",
                           fmt("the volume would reach %.4g ml, outside [%.3g, %.3g] ml (0.1x to 10x the rest volume)",
                               v_end / kMl, lo / kMl, hi / kMl));
        const double t_stop = r.t0 + (bound - v0) / r.value;
        report(o, r, ToolReportCode::FillStops, bound, t_stop);
        r.t1 = s.t1 = std::max(r.t0, t_stop);
      }
    } else {
      if (r.value < lo || r.value > hi) {
        if (constructing && !r.live)
          throw InputError(file_, r.line, field(r),
                           fmt("target %.4g ml is outside [%.3g, %.3g] ml (0.1x to 10x the rest volume)", r.value / kMl,
                               lo / kMl, hi / kMl));
        const double c = std::clamp(r.value, lo, hi);
        report(o, r, ToolReportCode::FillTargetClamped, r.value, c);
        r.value = c;
      }
      const double need = std::abs(r.value - v0) / max_rate_;
      if (need > (r.t1 - r.t0) * (1.0 + 1e-12)) {
        report(o, r, ToolReportCode::FillLengthened, r.value, r.t1 - r.t0, need);
        r.t1 = s.t1 = r.t0 + need;
      }
      s.slope = s.t1 > s.t0 ? (r.value - v0) / (s.t1 - s.t0) : 0.0;
    }
    o.seg.push_back(s);
  }
  o.cursor = 0;
}

double FillingTool::value_at(const Organ& o, size_t& cursor, double t) {
  if (o.seg.empty() || o.seg[0].t0 > t) return o.base;
  while (cursor + 1 < o.seg.size() && o.seg[cursor + 1].t0 <= t) ++cursor;
  const Segment& s = o.seg[cursor];
  return s.v0 + s.slope * (std::min(t, s.t1) - s.t0);
}

void FillingTool::boundary_conditions(const Model&, State& s, double dt) {
  now_ = s.time + dt;  // the volume projection acts at the end of the substep
  for (Organ& o : organs_) {
    o.current = value_at(o, o.cursor, now_);
    s.target_volume[o.surface] = o.current;
  }
}

FillingTool::Organ& FillingTool::organ(const std::string& component, const char* field) {
  for (Organ& o : organs_)
    if (o.name == component) return o;
  throw InputError("", 0, field, "'" + component + "' is not a filled organ (list it in the filling: section)");
}

void FillingTool::compact(Organ& o) {
  size_t in_force = 0;  // the last segment started at or before now_ (a later start takes over)
  bool any = false;
  for (size_t i = 0; i < o.raw.size(); ++i)
    if (o.raw[i].t0 <= now_) {
      in_force = i;
      any = true;
    }
  if (!any || in_force == 0) return;
  // resolve() starts segment in_force at exactly this value (the ended one's end): same bits
  o.base = o.seg[in_force].v0;
  o.raw.erase(o.raw.begin(), o.raw.begin() + static_cast<std::ptrdiff_t>(in_force));
  o.seg.erase(o.seg.begin(), o.seg.begin() + static_cast<std::ptrdiff_t>(in_force));
  o.cursor = 0;
}

size_t FillingTool::insert_live(Organ& o, const Raw& r) {
  compact(o);
  const auto pos = std::upper_bound(o.raw.begin(), o.raw.end(), now_, [](double t, const Raw& x) { return t < x.t0; });
  const size_t idx = static_cast<size_t>(pos - o.raw.begin());
  o.raw.insert(pos, r);  // within the reserved slots (at most two live segments after compact)
  resolve(o, false);
  return idx;
}

double FillingTool::set_rate(const std::string& component, double rate) {
  Organ& o = organ(component, "filling.set_rate.component");
  if (!std::isfinite(rate)) throw InputError("", 0, "filling.set_rate.rate", "rate must be finite");
  const size_t idx = insert_live(o, Raw{FillSpec::Rate, rate, now_, std::numeric_limits<double>::infinity(), -1, 0, true});
  return o.raw[idx].value;
}

double FillingTool::fill_to(const std::string& component, double target, double duration) {
  Organ& o = organ(component, "filling.fill_to.component");
  if (!(target > 0.0) || !std::isfinite(target)) throw InputError("", 0, "filling.fill_to.target", "a target volume must be > 0");
  if (!(duration >= 0.0) || !std::isfinite(duration)) throw InputError("", 0, "filling.fill_to.duration", "must be >= 0");
  const size_t idx = insert_live(o, Raw{FillSpec::Target, target, now_, now_ + duration, -1, 0, true});
  return o.raw[idx].t1 - now_;
}

double FillingTool::target_volume(const std::string& component) const {
  for (const Organ& o : organs_)
    if (o.name == component) return o.current;
  throw InputError("", 0, "filling.component", "'" + component + "' is not a filled organ");
}

std::unique_ptr<FillingTool> make_filling_tool(const ScenarioSpec& spec, const Model& model) {
  if (!spec.filling) return nullptr;
  return std::make_unique<FillingTool>(*spec.filling, model);
}

}  // namespace ps
