// Organs by component and tag name, the one place the needle's events, the metrics and the
// windows read them from.
#include "engine/model/organ.h"

#include <gtest/gtest.h>

namespace ps {
namespace {

Component named(const std::string& n, ComponentKind k = ComponentKind::Elastic) {
  Component c;
  c.name = n;
  c.kind = k;
  return c;
}

TEST(Organ, ComponentsByNameAndKind) {
  EXPECT_EQ(component_organ(named("prostate")), Organ::Gland);
  EXPECT_EQ(component_organ(named("Bladder")), Organ::Bladder);
  EXPECT_EQ(component_organ(named("rectum")), Organ::Rectum);
  EXPECT_EQ(component_organ(named("urethra")), Organ::Urethra);
  EXPECT_EQ(component_organ(named("tumour_2")), Organ::Lesion);
  EXPECT_EQ(component_organ(named("pubic_arch", ComponentKind::Rigid)), Organ::Bone);
  EXPECT_EQ(component_organ(named("fat")), Organ::Other);
  EXPECT_TRUE(is_lesion_name("lesion"));
  EXPECT_TRUE(is_lesion_name("Tumor"));
  EXPECT_FALSE(is_lesion_name("peripheral"));
  EXPECT_STREQ(organ_name(Organ::Rectum), "rectal wall");
}

}  // namespace
}  // namespace ps
