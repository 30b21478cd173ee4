// Acoustic table of the tissue classes. Echogenicities are relative backscatter amplitudes with the
// peripheral zone = 1 (TRUS reading convention: the PZ is the isoechoic reference; transition zone
// and anterior stroma darker, cancer hypoechoic, periprostatic fat hyperechoic, urine anechoic:
// Hricak/Choyke, "Prostate imaging", and the TRUS atlas of Halpern 2008). Attenuation one way in
// dB/(cm MHz) (Duck 1990, "Physical properties of tissue", ch. 4; the table of Diagnostics 13:855,
// 2023, Table 4: water 0.0022, adipose 0.63, muscle 0.96-1.40, bone 15): prostate 0.7 (in vitro
// 0.78, Parker 1983 lists 0.5-1.0 for soft organs), fat 0.63, other soft tissue 0.6, urine and the
// water-filled balloon 0.0022, bone 15 (a 6 mm rib of it: > 100 dB round trip at 7.5 MHz, a full
// shadow). Gas is given 80: its shadow comes from reflection (99.9 % of the intensity), not bulk
// absorption, and must be total within ~1 mm. Speed of sound: 1540 m/s throughout (the scanner's
// assumption, imager.h), so no refraction or range distortion is modelled. Seminal vesicles: on TRUS
// hypoechoic to the gland with a mottled inside (fluid in convoluted tubules between echogenic
// folds; Halpern 2008) and a thin wall: echo 0.25 with a +-50 % texture, attenuation 0.3 (mostly
// fluid, between urine and soft tissue). Interfaces: amplitude reflection (Z2 - Z1) / (Z2 + Z1) with
// Z = 1.63 (soft tissue), 1.38 (fat), 7.8 MRayl (cortical bone; Duck 1990): ~0.08 at the capsule,
// ~0.65 at bone, so bone's specular term is ten times the capsule's (3.0): its surface is the
// brightest line on the image, as a sonographer expects of the pubic bone.
#include "engine/ultrasound/scene.h"

namespace ps::us {

const TissueAcoustics& acoustics(Tissue t) {
  //                                   echo  hetero atten interface diffuse wall    wall_echo
  static const TissueAcoustics kProstate{1.0f, 0.25f, 0.7f, 3.0f, 3.5f, 0.0f, 0.0f};
  static const TissueAcoustics kFat{1.5f, 0.8f, 0.63f, 0.0f, 0.0f, 0.0f, 0.0f};
  static const TissueAcoustics kBladder{0.0f, 0.0f, 0.0022f, 4.0f, 1.0f, 2.0e-3f, 0.8f};
  static const TissueAcoustics kRectum{0.0f, 0.0f, 0.0022f, 2.0f, 1.2f, 3.0e-3f, 0.35f};
  static const TissueAcoustics kBone{0.0f, 0.0f, 15.0f, 30.0f, 4.0f, 0.0f, 0.0f};
  static const TissueAcoustics kGas{0.0f, 0.0f, 80.0f, 12.0f, 6.0f, 0.0f, 0.0f};
  static const TissueAcoustics kSeminalVesicle{0.25f, 0.5f, 0.3f, 0.6f, 0.4f, 0.0f, 0.0f};
  static const TissueAcoustics kSoft{1.0f, 0.0f, 0.6f, 0.8f, 0.4f, 0.0f, 0.0f};
  switch (t) {
    case Tissue::Prostate: return kProstate;
    case Tissue::Fat: return kFat;
    case Tissue::Bladder: return kBladder;
    case Tissue::Rectum: return kRectum;
    case Tissue::Bone: return kBone;
    case Tissue::Gas: return kGas;
    case Tissue::SeminalVesicle: return kSeminalVesicle;
    case Tissue::Soft: break;
  }
  return kSoft;
}

}  // namespace ps::us
