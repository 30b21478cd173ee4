// What a component or a particle tag stands for in the anatomy: the gland, a lesion, the urethra,
// the bladder... The scenario says it with `role:` on a component or a tag; compile_scenario
// resolves it once into Component::role and Model::tag_roles, and the needle's events, the
// session metrics, the ultrasound, the renderer and the editor read it from there. A name only
// decides when `role:` is absent, through default_role() below (the one place a name is read).
#pragma once
#include <string>

namespace ps {

enum class Role : unsigned char { Other, Prostate, Lesion, Urethra, Bladder, Rectum, Bone, Fat, Skin, Gas };

// The `role:` word of each role: "other", "prostate", "lesion", "urethra", "bladder", "rectum",
// "bone", "fat", "skin", "gas".
const char* role_word(Role r);
// The role a `role:` word names (exact, lower case); false for any other word.
bool parse_role(const std::string& word, Role* out);
// The accepted words, comma-separated, for error messages.
const char* role_words();

// The role of a component (rigid: true for a rigid component) or a tag (rigid: false) that has no
// `role:`, from its name, case-insensitive, first match wins:
//   a rigid component                     -> bone
//   "lesion" or "tumo" (tumour, tumor)    -> lesion
//   "urethra"                             -> urethra
//   "rect" (rectum, rectal_wall)          -> rectum
//   "bladder"                             -> bladder
//   "prostat" or "gland"                  -> prostate
//   "gas"                                 -> gas
//   "bone", "pubi" or "pelv"              -> bone
//   "fat"                                 -> fat
//   "skin"                                -> skin
//   anything else                         -> other
Role default_role(const std::string& name, bool rigid);

// The role given by `word` (a `role:` value the parser has accepted), or default_role() when
// `word` is empty. Code that has only the ScenarioSpec (no compiled Model) resolves with this.
Role resolve_role(const std::string& word, const std::string& name, bool rigid);

// What a needle event or a report calls the structure: "gland", "lesion", "urethra", "bladder",
// "rectal wall", "bone", "fat", "skin", "gas", "" (other).
const char* role_label(Role r);

}  // namespace ps
