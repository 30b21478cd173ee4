// What an instrument looks like, told to whoever draws (Box2D's b2DebugDraw pattern): a tool
// describes itself through this const interface, so render/ knows no tool internals and a new
// tool draws without touching render/. The engine never includes GL; DrawList records the calls
// into plain arrays that cross threads inside a Snapshot (engine/contract/snapshot.h).
// All positions and lengths in metres, world frame (patient RAS, see config/*.yaml).
#pragma once
#include <cstdint>
#include <vector>

#include "engine/util/vec.h"

namespace ps {

struct Rgba {
  float r = 1, g = 1, b = 1, a = 1;  // linear colour, alpha 1 = opaque
};

// What a primitive stands for: lets a renderer (or the ultrasound) style or filter by meaning.
enum class DrawRole : uint8_t {
  Other, Needle, NeedleTip, DepthMark, Probe, Guide, TemplateGrid, Seed, Target, Lesion, Force,
  Bone, CoreSample
};

class DrawSink {
 public:
  virtual ~DrawSink() = default;
  // thin line from a to b [m]
  virtual void segment(const Vec3& a, const Vec3& b, Rgba c, DrawRole role) = 0;
  // solid cylinder of the given radius with hemispherical ends (needle shaft, probe body) [m]
  virtual void capsule(const Vec3& a, const Vec3& b, double radius, Rgba c, DrawRole role) = 0;
  // solid sphere (tip, seed, target) [m]
  virtual void sphere(const Vec3& centre, double radius, Rgba c, DrawRole role) = 0;
  // arrow from a point along a vector already scaled to metres (force arrows: caller scales N->m)
  virtual void arrow(const Vec3& from, const Vec3& vec, Rgba c, DrawRole role) = 0;
};

struct DrawSegment { Vec3 a, b; Rgba c; DrawRole role; };
struct DrawCapsule { Vec3 a, b; double radius; Rgba c; DrawRole role; };
struct DrawSphere { Vec3 centre; double radius; Rgba c; DrawRole role; };
struct DrawArrow { Vec3 from, vec; Rgba c; DrawRole role; };

// Records the calls. clear() keeps capacity, so once warm a frame's recording does not allocate.
class DrawList final : public DrawSink {
 public:
  void segment(const Vec3& a, const Vec3& b, Rgba c, DrawRole role) override {
    segments.push_back({a, b, c, role});
  }
  void capsule(const Vec3& a, const Vec3& b, double radius, Rgba c, DrawRole role) override {
    capsules.push_back({a, b, radius, c, role});
  }
  void sphere(const Vec3& centre, double radius, Rgba c, DrawRole role) override {
    spheres.push_back({centre, radius, c, role});
  }
  void arrow(const Vec3& from, const Vec3& vec, Rgba c, DrawRole role) override {
    arrows.push_back({from, vec, c, role});
  }
  void clear() {
    segments.clear();
    capsules.clear();
    spheres.clear();
    arrows.clear();
  }
  // replays the recording into another sink (the renderer's batcher)
  void replay(DrawSink& out) const {
    for (const auto& s : segments) out.segment(s.a, s.b, s.c, s.role);
    for (const auto& s : capsules) out.capsule(s.a, s.b, s.radius, s.c, s.role);
    for (const auto& s : spheres) out.sphere(s.centre, s.radius, s.c, s.role);
    for (const auto& s : arrows) out.arrow(s.from, s.vec, s.c, s.role);
  }

  std::vector<DrawSegment> segments;
  std::vector<DrawCapsule> capsules;
  std::vector<DrawSphere> spheres;
  std::vector<DrawArrow> arrows;
};

}  // namespace ps
