#pragma once
// The text of a BVH file, checked but not yet interpreted (body/bvh.h turns it
// into a Motion): the joints and end sites as written, and the MOTION rows.
// Internal to body/bvh.cpp.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace pleat::bvh {

enum Channel : int8_t { kXpos, kYpos, kZpos, kXrot, kYrot, kZrot };

struct RawJoint {
  std::string name;
  int32_t parent = -1;
  int32_t line = 0;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  bool has_offset = false;
  bool has_channels = false;
  std::vector<Channel> channels;
  int32_t first_channel = 0;  // column of its first value in a MOTION row
};

struct RawEnd {
  int32_t joint = 0;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
};

struct RawBvh {
  std::vector<RawJoint> joints;  // parents first
  std::vector<RawEnd> ends;
  int32_t channel_count = 0;
  int64_t frame_count = 0;
  double frame_time = 0;       // seconds, > 0
  std::vector<double> values;  // frame_count x channel_count, finite
};

// Throws PLEAT_ERROR_FORMAT "<source>:<line>: <what>" for anything malformed.
RawBvh parse_bvh_text(const std::string& text, const std::string& source);

}  // namespace pleat::bvh
