/* Internal to the model layer: what decides which law a joint follows. */
#ifndef VS_MODEL_JOINT_LAW_H
#define VS_MODEL_JOINT_LAW_H

#include "voussoir/joint.h"

/* A joint whose law has mortar or damage (joint.h, vs_joint_law's ft, c, crack, env_*): its
 * normal and shear responses are vs_joint_normal_mortar's and vs_joint_shear_mortar's; else the
 * dry law's, bit for bit. */
static inline int vs_joint_law_is_mortar(const vs_joint_law *law) {
  return law->ft > 0.0 || law->c > 0.0 || law->crack[0] > 0.0 || law->crack[1] > 0.0 ||
         law->env_n > 0;
}

#endif
