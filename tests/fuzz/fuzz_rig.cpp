// Rigged characters and their clips (.glb) through tinygltf, pleat's checked
// walk of the scene (io/gltf_scene) and of skins and animations
// (body/rig_import): a body that validates, weights on
// existing joints, finite clips on the rig's skeleton.
#include <cmath>

#include "body/rig_import.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pleat_fuzz::run([&] {
    const pleat::ImportedRig rig = pleat::import_rig(pleat_fuzz::input_file(data, size, "in.glb"));
    const pleat::Body& body = rig.body;
    pleat_fuzz::require_valid_mesh(body.rest.vertices, body.rest.triangles);
    bool valid = true;
    try {
      pleat::validate_body(body, "fuzz");
    } catch (const pleat::Error&) {
      valid = false;
    }
    pleat_fuzz::require(valid, "import_rig returns a body that validates");
    const int32_t joints = body.joint_count();
    for (size_t i = 0; i < body.weights.joints.size(); ++i)
      pleat_fuzz::require(body.weights.joints[i] >= 0 && body.weights.joints[i] < joints &&
                              std::isfinite(body.weights.weights[i]),
                          "skin weights on existing joints, finite");
    for (const pleat::ImportedClip& clip : rig.clips) {
      const pleat::Motion& m = clip.motion;
      pleat_fuzz::require(m.skeleton.joint_count() == joints, "a clip on the rig's skeleton");
      pleat_fuzz::require(static_cast<int64_t>(m.rotations.size()) == m.frame_count * joints &&
                              m.root_translation.rows() == m.frame_count,
                          "clip sizes agree");
      pleat_fuzz::require(m.root_translation.allFinite(), "root path finite");
      for (const Eigen::Quaterniond& q : m.rotations)
        pleat_fuzz::require(std::isfinite(q.w()) && std::abs(q.norm() - 1.0) < 1e-6, "unit rotations");
    }
  });
}
