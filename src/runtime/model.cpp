#include "runtime/model.h"

namespace pleat::runtime {

int32_t feature_width(Feature feature, int32_t joint_count, int32_t shape_count) {
  switch (feature) {
    case Feature::shape: return shape_count;
    case Feature::rest_joint_distances:
    case Feature::posed_joint_distances: return joint_count;
    case Feature::joint_rotations_6d: return 6 * joint_count;
    case Feature::rest_position:
    case Feature::rest_normal:
    case Feature::root_velocity:
    case Feature::velocity:
    case Feature::normal: return 3;
  }
  return -1;
}

const char* feature_name(Feature feature) {
  switch (feature) {
    case Feature::shape: return "shape";
    case Feature::rest_joint_distances: return "rest_joint_distances";
    case Feature::rest_position: return "rest_position";
    case Feature::rest_normal: return "rest_normal";
    case Feature::joint_rotations_6d: return "joint_rotations_6d";
    case Feature::root_velocity: return "root_velocity";
    case Feature::velocity: return "velocity";
    case Feature::normal: return "normal";
    case Feature::posed_joint_distances: return "posed_joint_distances";
  }
  return "unknown";
}

}  // namespace pleat::runtime
