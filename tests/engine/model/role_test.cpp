// Roles of components and tags: the `role:` words and the name defaults (default_role), the one
// place a name decides what a component stands for.
#include "engine/model/role.h"

#include <gtest/gtest.h>

namespace ps {
namespace {

TEST(Role, NameDefaultsOfComponentsAndTags) {
  EXPECT_EQ(default_role("prostate", false), Role::Prostate);
  EXPECT_EQ(default_role("phantom_prostate", false), Role::Prostate);
  EXPECT_EQ(default_role("gland", false), Role::Prostate);
  EXPECT_EQ(default_role("Bladder", false), Role::Bladder);
  EXPECT_EQ(default_role("rectum", false), Role::Rectum);
  EXPECT_EQ(default_role("rectal_wall", false), Role::Rectum);
  EXPECT_EQ(default_role("urethra", false), Role::Urethra);
  EXPECT_EQ(default_role("tumour_2", false), Role::Lesion);
  EXPECT_EQ(default_role("Tumor", false), Role::Lesion);
  EXPECT_EQ(default_role("lesion_1", false), Role::Lesion);
  EXPECT_EQ(default_role("pubic_arch", true), Role::Bone);
  EXPECT_EQ(default_role("pubic_arch", false), Role::Bone);
  EXPECT_EQ(default_role("block", true), Role::Bone);      // any rigid component
  EXPECT_EQ(default_role("fat", false), Role::Fat);
  EXPECT_EQ(default_role("skin", false), Role::Skin);
  EXPECT_EQ(default_role("rectal_gas", false), Role::Rectum);  // first match wins
  EXPECT_EQ(default_role("gas", false), Role::Gas);
  EXPECT_EQ(default_role("peripheral", false), Role::Other);
  EXPECT_EQ(default_role("tissue", false), Role::Other);
}

TEST(Role, WordsRoundTripAndUnknownWordsAreRefused) {
  for (Role r : {Role::Other, Role::Prostate, Role::Lesion, Role::Urethra, Role::Bladder, Role::Rectum, Role::Bone, Role::Fat,
                 Role::Skin, Role::Gas}) {
    Role back = Role::Other;
    ASSERT_TRUE(parse_role(role_word(r), &back)) << role_word(r);
    EXPECT_EQ(back, r);
    EXPECT_NE(std::string(role_words()).find(role_word(r)), std::string::npos);
  }
  Role x = Role::Bladder;
  EXPECT_FALSE(parse_role("kidney", &x));
  EXPECT_FALSE(parse_role("Prostate", &x));  // the words are exact
  EXPECT_EQ(x, Role::Bladder);
}

TEST(Role, AGivenRoleWinsOverTheName) {
  EXPECT_EQ(resolve_role("bladder", "gland_left_thing", false), Role::Bladder);
  EXPECT_EQ(resolve_role("", "gland_left_thing", false), Role::Prostate);
  EXPECT_EQ(resolve_role("other", "tumour", false), Role::Other);
  EXPECT_EQ(resolve_role("lesion", "spot", false), Role::Lesion);
  EXPECT_STREQ(role_label(Role::Rectum), "rectal wall");
  EXPECT_STREQ(role_label(Role::Prostate), "gland");
  EXPECT_STREQ(role_label(Role::Other), "");
}

}  // namespace
}  // namespace ps
