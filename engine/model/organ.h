// Which organ a component or a particle tag stands for (the bladder, the urethra, a lesion...).
// Read from the names the scenario gives (the default anatomy's "prostate", "bladder", "rectum",
// tags "lesion*" / "tumo*"), in this one place, so that the needle's events, the session metrics
// and the windows agree on what counts as the bladder or a lesion.
#pragma once
#include <string>

#include "engine/model/model.h"

namespace ps {

enum class Organ : unsigned char { Other, Gland, Urethra, Rectum, Bladder, Bone, Lesion };

// The organ of a component: rigid components are bone; otherwise by name (case-insensitive):
// "prostate" or "gland" -> Gland, "urethra" -> Urethra, "rect" -> Rectum, "bladder" -> Bladder,
// "tumo" or "lesion" -> Lesion.
Organ component_organ(const Component& c);
// A tag or component name that stands for tumour tissue ("lesion", "tumour", "tumor_2", ...).
bool is_lesion_name(const std::string& name);
const char* organ_name(Organ o);  // "gland", "urethra", "rectal wall", "bladder", "bone", "lesion", ""

}  // namespace ps
