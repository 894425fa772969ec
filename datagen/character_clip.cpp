#include "character_clip.h"

#include "body/body_source.h"
#include "body/motion_file.h"
#include "body/motion_ops.h"
#include "capi/pleat.h"

namespace pleat::datagen {

uint32_t makehuman_rig(const std::string& rig) {
  return rig == "default" ? PLEAT_RIG_MAKEHUMAN_DEFAULT : PLEAT_RIG_CMU_MB;
}

CharacterClip load_character_clip(const std::string& body, const std::string& rig,
                                  const std::vector<std::pair<std::string, double>>& shape,
                                  const std::string& motion, const std::string& map, double frame_rate) {
  BodySource source = load_body_source(body, PLEAT_BODY_AUTO, makehuman_rig(rig));
  CharacterClip c;
  c.body = shape.empty() ? source.body : source.reshape(shape_values(source.body, shape));
  RetargetOptions options;
  JointMap joint_map;
  if (!map.empty()) {
    joint_map = read_joint_map(map);
    options.map = &joint_map;
  }
  c.clip =
      retarget_motion(resample_motion(read_motion_file(motion).motion, frame_rate), c.body.skeleton, options);
  return c;
}

}  // namespace pleat::datagen
