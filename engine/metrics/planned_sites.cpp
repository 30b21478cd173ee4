#include "engine/metrics/planned_sites.h"

#include <algorithm>
#include <sstream>

namespace ps {

std::vector<PlannedSite> planned_sites(const Model& m, const std::vector<std::string>& labels) {
  std::vector<PlannedSite> out;
  // the gland's antero-posterior extent (y: anterior, the zones' frame, engine/anatomy/zones.h)
  double gland_lo = 1e300, gland_hi = -1e300;
  uint64_t zone_bits = 0;
  for (const char* z : {"peripheral", "transition", "anterior"})
    if (const int t = m.find_tag(z); t >= 0) zone_bits |= uint64_t{1} << t;
  for (int p = 0; p < m.particle_count() && zone_bits; ++p)
    if (m.particle_tags[p] & zone_bits) {
      gland_lo = std::min(gland_lo, m.rest_pos[p].y());
      gland_hi = std::max(gland_hi, m.rest_pos[p].y());
    }
  for (const std::string& label : labels) {
    PlannedSite site;
    site.label = label;
    uint64_t need = 0;
    bool known = !m.particle_tags.empty();
    std::istringstream words(label + " peripheral");
    std::string w;
    while (words >> w) {
      const int t = m.find_tag(w);
      if (t < 0) { known = false; break; }
      need |= uint64_t{1} << t;
    }
    if (known) {
      // the site's peripheral-zone tissue in the posterior half of the gland (the PZ shell also
      // runs up the sides; a systematic core aims at its posterior and posterolateral part,
      // within the needle's reach from the rectum), all of it if none lies there
      double y_mid = 0.5 * (gland_lo + gland_hi);
      for (int pass = 0; pass < 2 && site.particles == 0; ++pass) {
        Vec3 sum = Vec3::Zero();
        for (int p = 0; p < m.particle_count(); ++p)
          if ((m.particle_tags[p] & need) == need && (pass == 1 || m.rest_pos[p].y() <= y_mid)) { sum += m.rest_pos[p]; ++site.particles; }
        if (site.particles > 0) site.centre = sum / site.particles;
        y_mid = 1e300;
      }
    }
    out.push_back(site);
  }
  return out;
}

double distance_to_segment(const Vec3& c, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0.0 ? std::clamp((c - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (c - (a + t * ab)).norm();
}

}  // namespace ps
