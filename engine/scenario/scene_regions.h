// Scenario features the anatomy needs, called from compile_scenario():
//  - exclude_inside: a volumetric component (the pelvic fat block) filled everywhere except
//    inside the organs it surrounds;
//  - tags: / prostate_zones: named particle tags stored in Model::tag_names / particle_tags.
#pragma once
#include <array>
#include <vector>

#include "engine/model/model.h"
#include "engine/scenario/particle_set.h"
#include "engine/spec/scenario_spec.h"

namespace ps::anatomy {

// Lattice fill of component `ci` (its box, cylinder or mesh surface, as for any volumetric
// component) that leaves out points inside, or within 0.45 spacing of, the closed surfaces of
// the components it lists in exclude_inside (taken from `sets`, already built). Every listed
// component must lie inside this one, and no surface particle of this one may fall inside a
// listed component, nor a particle of one listed component inside another (overlapping organs)
// (InputError naming the key and the point otherwise). *excluded_volume receives the summed
// volume enclosed by the listed components [m^3], which is not this component's material.
ParticleSet fill_excluding(const ScenarioSpec& spec, size_t ci, const std::vector<ParticleSet>& sets,
                           double* excluded_volume);

// Fills model.tag_names / model.particle_tags from spec.prostate_zones (the kZoneTagNames, first)
// and spec.tags (in file order). Needs rest_pos, component ranges and each component's surface
// faces (global particle indices). InputError when a tag selects no particle, a tag name clashes
// with a zone name, or there are more than 64 tags.
void apply_particle_tags(const ScenarioSpec& spec, Model& model,
                         const std::vector<std::vector<std::array<int, 3>>>& faces_of_component);

// The centres [m] of the lesions `lesions:` places (spec.lesions, needs its prostate_zones), drawn
// from the seed among the gland's particles carrying the zone tag, a diameter apart; each lesion
// is the sphere of the diameter around its centre (its particles within, at rest). The model needs
// the zone tags (a compiled model has them). InputError naming `lesions.*` when they do not fit.
std::vector<Vec3> seeded_lesion_centres(const ScenarioSpec& spec, const Model& model);

}  // namespace ps::anatomy
