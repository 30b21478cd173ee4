// Acoustic table of the tissue classes. Echogenicities are relative backscatter amplitudes with the
// peripheral zone = 1 (TRUS reading convention: the PZ is the isoechoic reference; transition zone
// and anterior stroma darker, cancer hypoechoic, periprostatic fat hyperechoic, urine anechoic:
// Hricak/Choyke, "Prostate imaging", and the TRUS atlas of Halpern 2008). Attenuation one way in
// dB/(cm MHz): soft tissue ~0.5-0.8 (prostate 0.78 in vitro, Parker 1983 lists 0.5-1.0), fat
// ~0.6, water/urine ~0.002, bone ~20 (Duck 1990, "Physical properties of tissue"). Bone and gas
// are given an attenuation far above their measured bulk values so that their shadow is total
// within ~1 mm, which is what the reflection (bone ~50 %, gas ~99.9 % of the intensity) does.
#include "engine/ultrasound/scene.h"

namespace ps::us {

const TissueAcoustics& acoustics(Tissue t) {
  //                                   echo  hetero atten interface diffuse wall    wall_echo
  static const TissueAcoustics kProstate{1.0f, 0.25f, 0.6f, 3.0f, 3.5f, 0.0f, 0.0f};
  static const TissueAcoustics kFat{1.5f, 0.8f, 0.6f, 0.0f, 0.0f, 0.0f, 0.0f};
  static const TissueAcoustics kBladder{0.0f, 0.0f, 0.002f, 2.5f, 1.0f, 2.0e-3f, 0.8f};
  static const TissueAcoustics kRectum{0.0f, 0.0f, 0.002f, 2.0f, 1.2f, 3.0e-3f, 0.35f};
  static const TissueAcoustics kBone{0.0f, 0.0f, 40.0f, 10.0f, 4.0f, 0.0f, 0.0f};
  static const TissueAcoustics kGas{0.0f, 0.0f, 80.0f, 12.0f, 6.0f, 0.0f, 0.0f};
  static const TissueAcoustics kSoft{1.0f, 0.0f, 0.6f, 0.8f, 0.4f, 0.0f, 0.0f};
  switch (t) {
    case Tissue::Prostate: return kProstate;
    case Tissue::Fat: return kFat;
    case Tissue::Bladder: return kBladder;
    case Tissue::Rectum: return kRectum;
    case Tissue::Bone: return kBone;
    case Tissue::Gas: return kGas;
    case Tissue::Soft: break;
  }
  return kSoft;
}

}  // namespace ps::us
