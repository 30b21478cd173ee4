#include "engine/model/role.h"

#include <cctype>

namespace ps {

namespace {

constexpr Role kAll[] = {Role::Other, Role::Prostate, Role::Lesion, Role::Urethra, Role::Bladder,
                         Role::Rectum, Role::Bone,     Role::Fat,    Role::Skin,    Role::Gas};

}  // namespace

const char* role_word(Role r) {
  switch (r) {
    case Role::Other: return "other";
    case Role::Prostate: return "prostate";
    case Role::Lesion: return "lesion";
    case Role::Urethra: return "urethra";
    case Role::Bladder: return "bladder";
    case Role::Rectum: return "rectum";
    case Role::Bone: return "bone";
    case Role::Fat: return "fat";
    case Role::Skin: return "skin";
    case Role::Gas: return "gas";
  }
  return "other";
}

bool parse_role(const std::string& word, Role* out) {
  for (Role r : kAll)
    if (word == role_word(r)) {
      *out = r;
      return true;
    }
  return false;
}

const char* role_words() { return "prostate, lesion, urethra, bladder, rectum, bone, fat, skin, gas, other"; }

Role default_role(const std::string& name, bool rigid) {
  if (rigid) return Role::Bone;
  std::string n = name;
  for (char& ch : n) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  auto has = [&](const char* w) { return n.find(w) != std::string::npos; };
  if (has("lesion") || has("tumo")) return Role::Lesion;
  if (has("urethra")) return Role::Urethra;
  if (has("rect")) return Role::Rectum;
  if (has("bladder")) return Role::Bladder;
  if (has("prostat") || has("gland")) return Role::Prostate;
  if (has("gas")) return Role::Gas;
  if (has("bone") || has("pubi") || has("pelv")) return Role::Bone;
  if (has("fat")) return Role::Fat;
  if (has("skin")) return Role::Skin;
  return Role::Other;
}

Role resolve_role(const std::string& word, const std::string& name, bool rigid) {
  Role r = Role::Other;
  if (!word.empty() && parse_role(word, &r)) return r;
  return default_role(name, rigid);
}

const char* role_label(Role r) {
  switch (r) {
    case Role::Prostate: return "gland";
    case Role::Rectum: return "rectal wall";
    case Role::Other: return "";
    default: return role_word(r);
  }
}

}  // namespace ps
