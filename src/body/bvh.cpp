#include "body/bvh.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "body/bvh_text.h"
#include "core/error.h"

namespace pleat {

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

using bvh::Channel;
using bvh::RawBvh;
using bvh::RawJoint;

// Metres per file unit: given, or the known unit that makes the figure
// closest to 1.7 m when that lands between 1 and 2.6 m, else a fit to 1.7 m.
void choose_scale(const BvhOptions& options, BvhConversion* conv) {
  if (options.scale > 0.0) {
    conv->scale = options.scale;
    conv->unit = "given";
    return;
  }
  struct UnitGuess {
    double scale;
    const char* name;
  };
  static const UnitGuess kUnits[] = {{1.0, "metre"},       {0.1, "decimetre"},
                                     {0.01, "centimetre"}, {0.001, "millimetre"},
                                     {0.0254, "inch"},     {0.0254 / 0.45, "CMU ASF unit (1/0.45 inch)"}};
  conv->scale_guessed = true;
  const double h = conv->height_file_units;
  if (!(h > 0.0)) {
    conv->scale = 1.0;
    conv->unit = "metre (no height to guess from)";
    return;
  }
  const UnitGuess* best = &kUnits[0];
  for (const UnitGuess& u : kUnits)
    if (std::abs(std::log(h * u.scale / 1.7)) < std::abs(std::log(h * best->scale / 1.7))) best = &u;
  const double metres = h * best->scale;
  if (metres >= 1.0 && metres <= 2.6) {
    conv->scale = best->scale;
    conv->unit = best->name;
  } else {
    conv->scale = 1.7 / h;
    conv->unit = "fit to 1.7 m";
  }
}

// The rest skeleton's extent (joints and end sites, file units and axes).
Eigen::Vector3d rest_extent(const RawBvh& raw) {
  std::vector<Eigen::Vector3d> rest(raw.joints.size());
  std::vector<Eigen::Vector3d> points;
  for (size_t j = 0; j < raw.joints.size(); ++j) {
    const RawJoint& joint = raw.joints[j];
    rest[j] = joint.offset +
              (joint.parent >= 0 ? rest[static_cast<size_t>(joint.parent)] : Eigen::Vector3d::Zero());
    points.push_back(rest[j]);
  }
  for (const bvh::RawEnd& e : raw.ends) points.push_back(rest[static_cast<size_t>(e.joint)] + e.offset);
  Eigen::Vector3d lo = points[0], hi = points[0];
  for (const auto& x : points) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  return hi - lo;
}

// Whether position channels add to OFFSET (MakeHuman) rather than replace it:
// the guess is "relative" when non-root position values of the first frame
// are small next to their OFFSETs.
bool positions_are_relative(const RawBvh& raw, BvhPositions positions) {
  if (positions != BvhPositions::kAuto) return positions == BvhPositions::kRelative;
  if (raw.frame_count == 0) return false;
  double value_sum = 0, offset_sum = 0;
  int count = 0;
  for (size_t j = 1; j < raw.joints.size(); ++j)
    for (size_t c = 0; c < raw.joints[j].channels.size(); ++c)
      if (raw.joints[j].channels[c] <= bvh::kZpos) {
        value_sum += std::abs(raw.values[static_cast<size_t>(raw.joints[j].first_channel) + c]);
        offset_sum += std::abs(raw.joints[j].offset[raw.joints[j].channels[c]]);
        ++count;
      }
  return count > 0 && value_sum < 0.1 * offset_sum;
}

// The skeleton in pleat conventions; `point` maps file offsets to metres, Y up.
template <typename Point>
void convert_skeleton(const RawBvh& raw, const std::string& source, Point point, BvhClip* clip) {
  const auto n = static_cast<int32_t>(raw.joints.size());
  Skeleton& sk = clip->motion.skeleton;
  sk.names.resize(static_cast<size_t>(n));
  sk.parents.resize(static_cast<size_t>(n));
  sk.rest_translation.resize(n, 3);
  sk.rest_rotation.assign(static_cast<size_t>(n), Eigen::Quaterniond::Identity());
  clip->rotation_orders.resize(static_cast<size_t>(n));
  for (int32_t j = 0; j < n; ++j) {
    const RawJoint& joint = raw.joints[static_cast<size_t>(j)];
    sk.names[static_cast<size_t>(j)] = joint.name;
    sk.parents[static_cast<size_t>(j)] = joint.parent;
    sk.rest_translation.row(j) = point(joint.offset).transpose();
    for (Channel c : joint.channels)
      if (c >= bvh::kXrot)
        clip->rotation_orders[static_cast<size_t>(j)] += static_cast<char>('X' + (c - bvh::kXrot));
  }
  try {
    validate_skeleton(sk, source);  // duplicate joint names
  } catch (const Error& e) {
    fail(PLEAT_ERROR_FORMAT, e.what());
  }
  for (const bvh::RawEnd& e : raw.ends) clip->end_sites.push_back({e.joint, point(e.offset)});
}

// Every MOTION row as joint rotations (rotated to Y up with `axes`) and the
// root's position; non-root position channels are dropped, their largest
// deviation from OFFSET recorded.
template <typename Point>
void convert_frames(const RawBvh& raw, bool relative, const Eigen::Quaterniond& axes, Point point,
                    BvhClip* clip) {
  Motion& m = clip->motion;
  BvhConversion& conv = clip->conversion;
  const auto n = static_cast<int32_t>(raw.joints.size());
  const bool rotate = conv.z_up_converted;  // axes is the identity otherwise
  m.frame_count = raw.frame_count;
  m.rotations.resize(static_cast<size_t>(m.frame_count) * static_cast<size_t>(n));
  m.root_translation.resize(m.frame_count, 3);
  const Eigen::Quaterniond axes_inv = axes.conjugate();
  static const Eigen::Vector3d kAxis[3] = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                           Eigen::Vector3d::UnitZ()};
  for (int64_t f = 0; f < m.frame_count; ++f) {
    const double* row = raw.values.data() + static_cast<size_t>(f) * static_cast<size_t>(raw.channel_count);
    Eigen::Quaterniond* out = m.rotations.data() + f * n;
    for (int32_t j = 0; j < n; ++j) {
      const RawJoint& joint = raw.joints[static_cast<size_t>(j)];
      Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
      Eigen::Vector3d position = joint.offset;
      bool has_position = false;
      Eigen::Vector3d given = relative ? Eigen::Vector3d::Zero() : joint.offset;
      for (size_t c = 0; c < joint.channels.size(); ++c) {
        const double v = row[static_cast<size_t>(joint.first_channel) + c];
        const Channel ch = joint.channels[c];
        if (ch >= bvh::kXrot) {
          q = q * Eigen::Quaterniond(Eigen::AngleAxisd(v * kDegree, kAxis[ch - bvh::kXrot]));
        } else {
          given[ch] = v;
          has_position = true;
        }
      }
      if (has_position) position = relative ? Eigen::Vector3d(joint.offset + given) : given;
      q.normalize();
      out[j] = rotate ? (axes * q * axes_inv).normalized() : q;
      if (j == 0) {
        m.root_translation.row(f) = point(position).transpose();
      } else if (has_position) {
        const double deviation = conv.scale * (position - joint.offset).norm();
        if (deviation > conv.dropped_translation_m) {
          conv.dropped_translation_m = deviation;
          conv.dropped_translation_joint = joint.name;
        }
      }
    }
  }
}

}  // namespace

std::string BvhConversion::summary() const {
  char buffer[512];
  std::snprintf(
      buffer, sizeof buffer,
      "scale %.6g m/unit (%s%s), height %.4g units = %.3f m, %s, %s root positions, frame time %.7g s%s",
      scale, unit.c_str(), scale_guessed ? ", guessed" : "", height_file_units, height_m,
      z_up_converted ? "Z up rotated to Y up" : "Y up", positions_relative ? "relative" : "absolute",
      frame_time, frame_rate_snapped ? " (rate snapped to a whole number)" : "");
  std::string s = buffer;
  if (joints_with_positions > 0)
    s += ", " + std::to_string(joints_with_positions) + " non-root joints with position channels";
  if (!dropped_translation_joint.empty())
    s += ", dropped non-root translations up to " + std::to_string(dropped_translation_m) + " m (joint '" +
         dropped_translation_joint + "')";
  return s;
}

Eigen::Quaterniond bvh_euler_rotation(const std::string& order, const Eigen::Vector3d& degrees) {
  if (order.size() != 3)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "bvh_euler_rotation: order '" + order + "' is not 3 axes");
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  for (int i = 0; i < 3; ++i) {
    Eigen::Vector3d axis;
    switch (order[static_cast<size_t>(i)]) {
      case 'X':
      case 'x': axis = Eigen::Vector3d::UnitX(); break;
      case 'Y':
      case 'y': axis = Eigen::Vector3d::UnitY(); break;
      case 'Z':
      case 'z': axis = Eigen::Vector3d::UnitZ(); break;
      default: fail(PLEAT_ERROR_INVALID_ARGUMENT, "bvh_euler_rotation: bad axis in '" + order + "'");
    }
    q = q * Eigen::Quaterniond(Eigen::AngleAxisd(degrees[i] * kDegree, axis));
  }
  return q.normalized();
}

BvhClip parse_bvh(const std::string& text, const std::string& source, const BvhOptions& options) {
  if (!(options.scale >= 0.0) || !std::isfinite(options.scale))
    fail(PLEAT_ERROR_INVALID_ARGUMENT, source + ": BVH scale must be finite and >= 0 (0 = guess)");
  const RawBvh raw = bvh::parse_bvh_text(text, source);
  BvhClip clip;
  BvhConversion& conv = clip.conversion;
  conv.channel_count = raw.channel_count;
  conv.frame_time = raw.frame_time;

  const Eigen::Vector3d extent = rest_extent(raw);
  bool z_up = options.up_axis == BvhUpAxis::kZ;
  if (options.up_axis == BvhUpAxis::kAuto) z_up = extent.z() > extent.y();
  conv.z_up_converted = z_up;
  conv.height_file_units = z_up ? extent.z() : extent.y();
  choose_scale(options, &conv);
  conv.height_m = conv.height_file_units * conv.scale;
  conv.positions_relative = positions_are_relative(raw, options.positions);
  for (size_t j = 1; j < raw.joints.size(); ++j)
    for (Channel c : raw.joints[j].channels)
      if (c <= bvh::kZpos) {
        ++conv.joints_with_positions;
        break;
      }

  double rate = 1.0 / raw.frame_time;
  if (options.snap_frame_rate) {
    const double whole = std::round(rate);
    if (whole >= 1.0 && std::abs(rate - whole) <= 1e-4 * rate && rate != whole) {
      rate = whole;
      conv.frame_rate_snapped = true;
    }
  }
  clip.motion.frame_rate = rate;

  // Axis change (Z up -> Y up: (x, y, z) -> (x, z, -y)) and scaling.
  const Eigen::Quaterniond axes =
      z_up ? Eigen::Quaterniond(Eigen::AngleAxisd(-90.0 * kDegree, Eigen::Vector3d::UnitX()))
           : Eigen::Quaterniond::Identity();
  const Eigen::Matrix3d axes_m = axes.toRotationMatrix();
  const double s = conv.scale;
  auto point = [&](const Eigen::Vector3d& v) -> Eigen::Vector3d { return s * (axes_m * v); };
  convert_skeleton(raw, source, point, &clip);
  convert_frames(raw, conv.positions_relative, axes, point, &clip);
  return clip;
}

BvhClip read_bvh(const std::string& path, const BvhOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(PLEAT_ERROR_IO, path + ": cannot open BVH file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) fail(PLEAT_ERROR_IO, path + ": read error");
  return parse_bvh(buffer.str(), path, options);
}

void bvh_frame_positions(const BvhClip& clip, int64_t frame, Points3d* joints, Points3d* end_sites) {
  const Motion& m = clip.motion;
  if (frame < 0 || frame >= m.frame_count)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "bvh_frame_positions: frame " + std::to_string(frame) +
                                           " outside [0, " + std::to_string(m.frame_count) + ")");
  Transforms global;
  forward_kinematics(m.skeleton, m.frame(frame), m.root_translation.row(frame).transpose(), &global);
  if (joints) {
    joints->resize(m.skeleton.joint_count(), 3);
    for (size_t j = 0; j < global.size(); ++j)
      joints->row(static_cast<Eigen::Index>(j)) = global[j].translation().transpose();
  }
  if (end_sites) {
    end_sites->resize(static_cast<Eigen::Index>(clip.end_sites.size()), 3);
    for (size_t e = 0; e < clip.end_sites.size(); ++e)
      end_sites->row(static_cast<Eigen::Index>(e)) =
          (global[clip.end_sites[e].joint] * clip.end_sites[e].offset).transpose();
  }
}

}  // namespace pleat
