#include "engine/model/organ.h"

#include <cctype>

namespace ps {

namespace {

bool has(const std::string& name, const char* word) {
  std::string l = name;
  for (char& ch : l) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return l.find(word) != std::string::npos;
}

}  // namespace

bool is_lesion_name(const std::string& name) { return has(name, "tumo") || has(name, "lesion"); }

Organ component_organ(const Component& c) {
  if (c.kind == ComponentKind::Rigid) return Organ::Bone;
  if (is_lesion_name(c.name)) return Organ::Lesion;
  if (has(c.name, "urethra")) return Organ::Urethra;
  if (has(c.name, "rect")) return Organ::Rectum;
  if (has(c.name, "bladder")) return Organ::Bladder;
  if (has(c.name, "prostate") || has(c.name, "gland")) return Organ::Gland;
  return Organ::Other;
}

const char* organ_name(Organ o) {
  switch (o) {
    case Organ::Gland: return "gland";
    case Organ::Urethra: return "urethra";
    case Organ::Rectum: return "rectal wall";
    case Organ::Bladder: return "bladder";
    case Organ::Bone: return "bone";
    case Organ::Lesion: return "lesion";
    case Organ::Other: break;
  }
  return "";
}

}  // namespace ps
