#include "io/bvh.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace pleat {

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

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

// One line split into whitespace-separated tokens.
struct Line {
  int32_t number = 0;  // 1-based
  std::vector<std::string_view> tokens;
};

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

void split_tokens(std::string_view line, std::vector<std::string_view>* tokens) {
  tokens->clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) tokens->push_back(line.substr(start, i - start));
  }
}

class Parser {
 public:
  Parser(const std::string& text, const std::string& source) : text_(text), source_(source) {}

  [[noreturn]] void error(int32_t line, const std::string& message) const {
    fail(PLEAT_ERROR_FORMAT, source_ + ":" + std::to_string(line) + ": " + message);
  }

  // Next line with at least one token; false at end of text.
  bool next_line(Line* out) {
    while (pos_ < text_.size()) {
      size_t end = text_.find('\n', pos_);
      if (end == std::string::npos) end = text_.size();
      std::string_view line(text_.data() + pos_, end - pos_);
      pos_ = end + 1;
      ++line_number_;
      split_tokens(line, &out->tokens);
      if (!out->tokens.empty()) {
        out->number = line_number_;
        return true;
      }
    }
    return false;
  }

  double number(std::string_view token, int32_t line, const std::string& what) const {
    double value = 0;
    const char* begin = token.data();
    const char* end = token.data() + token.size();
    if (begin != end && *begin == '+') ++begin;
    const auto result = std::from_chars(begin, end, value);
    if (result.ec != std::errc() || result.ptr != end)
      error(line, "'" + std::string(token) + "' is not a number (" + what + ")");
    if (!std::isfinite(value)) error(line, "non-finite value '" + std::string(token) + "' (" + what + ")");
    return value;
  }

  void parse() {
    Line line;
    if (!next_line(&line)) error(line_number_, "empty file, expected HIERARCHY");
    if (line.tokens[0] != "HIERARCHY")
      error(line.number, "expected HIERARCHY, found '" + std::string(line.tokens[0]) + "'");
    if (line.tokens.size() > 1) error(line.number, "unexpected text after HIERARCHY");
    if (!next_line(&line)) error(line_number_, "missing ROOT");
    if (line.tokens[0] != "ROOT")
      error(line.number, "expected ROOT, found '" + std::string(line.tokens[0]) + "'");
    parse_joint(line, -1);
    if (!next_line(&line)) error(line_number_, "missing MOTION section");
    if (line.tokens[0] == "ROOT")
      error(line.number, "a second ROOT: only one skeleton per file is supported");
    if (line.tokens[0] != "MOTION")
      error(line.number, "expected MOTION, found '" + std::string(line.tokens[0]) + "'");
    if (line.tokens.size() > 1) error(line.number, "unexpected text after MOTION");
    parse_motion();
  }

  // "ROOT name" / "JOINT name" already read into `line`.
  void parse_joint(const Line& header, int32_t parent, int depth = 0) {
    if (depth > 1000) error(header.number, "joints nested more than 1000 deep");
    if (header.tokens.size() < 2) error(header.number, std::string(header.tokens[0]) + " without a name");
    RawJoint joint;
    joint.parent = parent;
    joint.line = header.number;
    bool brace_on_header = false;
    for (size_t t = 1; t < header.tokens.size(); ++t) {
      if (header.tokens[t] == "{" && t + 1 == header.tokens.size() && t > 1) {
        brace_on_header = true;
        break;
      }
      if (!joint.name.empty()) joint.name += ' ';
      joint.name += header.tokens[t];
    }
    const int32_t index = static_cast<int32_t>(joints_.size());
    joints_.push_back(joint);
    Line line;
    if (!brace_on_header) {
      if (!next_line(&line)) error(line_number_, "unexpected end of file in joint '" + joint.name + "'");
      if (line.tokens[0] != "{" || line.tokens.size() != 1)
        error(line.number, "expected '{' after " + std::string(header.tokens[0]) + " " + joint.name);
    }
    for (;;) {
      if (!next_line(&line))
        error(line_number_, "unexpected end of file in joint '" + joint.name + "' (missing '}')");
      const std::string_view key = line.tokens[0];
      if (key == "}") {
        if (line.tokens.size() != 1) error(line.number, "unexpected text after '}'");
        break;
      }
      if (key == "OFFSET") {
        if (joints_[index].has_offset) error(line.number, "second OFFSET in joint '" + joint.name + "'");
        joints_[index].offset = read_offset(line, "OFFSET of joint '" + joint.name + "'");
        joints_[index].has_offset = true;
      } else if (key == "CHANNELS") {
        read_channels(line, index);
      } else if (key == "JOINT") {
        if (!joints_[index].has_offset)
          error(line.number, "joint '" + joint.name + "' has no OFFSET before its children");
        parse_joint(line, index, depth + 1);
      } else if (key == "End" || key == "END" || key == "end") {
        if (line.tokens.size() != 2 ||
            (line.tokens[1] != "Site" && line.tokens[1] != "site" && line.tokens[1] != "SITE"))
          error(line.number, "expected 'End Site'");
        parse_end_site(index);
      } else {
        error(line.number, "unknown keyword '" + std::string(key) + "' in joint '" + joint.name + "'");
      }
    }
    if (!joints_[index].has_offset) error(joint.line, "joint '" + joint.name + "' has no OFFSET");
    if (!joints_[index].has_channels) error(joint.line, "joint '" + joint.name + "' has no CHANNELS");
  }

  Eigen::Vector3d read_offset(const Line& line, const std::string& what) const {
    if (line.tokens.size() != 4)
      error(line.number, what + " needs 3 values, found " + std::to_string(line.tokens.size() - 1));
    return Eigen::Vector3d(number(line.tokens[1], line.number, what),
                           number(line.tokens[2], line.number, what),
                           number(line.tokens[3], line.number, what));
  }

  void read_channels(const Line& line, int32_t index) {
    RawJoint& joint = joints_[index];
    if (joint.has_channels) error(line.number, "second CHANNELS in joint '" + joint.name + "'");
    if (line.tokens.size() < 2) error(line.number, "CHANNELS without a count");
    const double count = number(line.tokens[1], line.number, "channel count");
    if (count < 0 || count > 6 || count != std::floor(count))
      error(line.number, "channel count must be 0..6, found " + std::string(line.tokens[1]));
    if (line.tokens.size() != static_cast<size_t>(count) + 2)
      error(line.number, "CHANNELS declares " + std::string(line.tokens[1]) + " channels but names " +
                             std::to_string(line.tokens.size() - 2));
    static const char* const kNames[] = {"Xposition", "Yposition", "Zposition",
                                         "Xrotation", "Yrotation", "Zrotation"};
    for (size_t t = 2; t < line.tokens.size(); ++t) {
      int found = -1;
      for (int c = 0; c < 6; ++c)
        if (line.tokens[t] == kNames[c]) found = c;
      if (found < 0) error(line.number, "unknown channel '" + std::string(line.tokens[t]) + "'");
      for (Channel seen : joint.channels)
        if (seen == found) error(line.number, "channel '" + std::string(line.tokens[t]) + "' repeated");
      joint.channels.push_back(static_cast<Channel>(found));
    }
    joint.has_channels = true;
    joint.first_channel = channel_count_;
    channel_count_ += static_cast<int32_t>(joint.channels.size());
  }

  void parse_end_site(int32_t joint) {
    Line line;
    if (!next_line(&line) || line.tokens[0] != "{" || line.tokens.size() != 1)
      error(line_number_, "expected '{' after End Site");
    RawEnd end;
    end.joint = joint;
    bool has_offset = false;
    for (;;) {
      if (!next_line(&line)) error(line_number_, "unexpected end of file in End Site");
      if (line.tokens[0] == "}") break;
      if (line.tokens[0] == "OFFSET" && !has_offset) {
        end.offset = read_offset(line, "OFFSET of an End Site of '" + joints_[joint].name + "'");
        has_offset = true;
      } else {
        error(line.number, "unexpected '" + std::string(line.tokens[0]) + "' in End Site (only one OFFSET)");
      }
    }
    if (!has_offset) error(line.number, "End Site without OFFSET");
    ends_.push_back(end);
  }

  void parse_motion() {
    Line line;
    if (!next_line(&line)) error(line_number_, "missing 'Frames:'");
    // "Frames: N" or "Frames : N"
    std::vector<std::string_view> t = line.tokens;
    if (t.size() == 3 && t[0] == "Frames" && t[1] == ":") t.erase(t.begin() + 1);
    if (t.size() != 2 || (t[0] != "Frames:")) error(line.number, "expected 'Frames: <count>'");
    const double frames = number(t[1], line.number, "frame count");
    if (frames < 0 || frames != std::floor(frames) || frames > 1e9)
      error(line.number, "bad frame count '" + std::string(t[1]) + "'");
    frame_count_ = static_cast<int64_t>(frames);
    if (!next_line(&line)) error(line_number_, "missing 'Frame Time:'");
    t = line.tokens;
    if (t.size() == 4 && t[0] == "Frame" && t[1] == "Time" && t[2] == ":") t.erase(t.begin() + 2);
    if (t.size() != 3 || t[0] != "Frame" || t[1] != "Time:")
      error(line.number, "expected 'Frame Time: <seconds>'");
    frame_time_ = number(t[2], line.number, "frame time");
    if (!(frame_time_ > 0)) error(line.number, "frame time must be positive, found " + std::string(t[2]));
    // Grow with the rows actually present: a lying header must not allocate.
    values_.reserve(static_cast<size_t>(std::min<int64_t>(frame_count_, 1 << 16)) *
                    static_cast<size_t>(channel_count_));
    int64_t row = 0;
    while (next_line(&line)) {
      if (row >= frame_count_)
        error(line.number, "more motion rows than 'Frames: " + std::to_string(frame_count_) + "'");
      if (static_cast<int32_t>(line.tokens.size()) != channel_count_)
        error(line.number, "frame " + std::to_string(row) + " has " + std::to_string(line.tokens.size()) +
                               " values, the hierarchy declares " + std::to_string(channel_count_) +
                               " channels");
      for (int32_t c = 0; c < channel_count_; ++c)
        values_.push_back(number(line.tokens[static_cast<size_t>(c)], line.number,
                                 "frame " + std::to_string(row) + ", value " + std::to_string(c + 1)));
      ++row;
    }
    if (row < frame_count_)
      error(line_number_, "truncated MOTION data: " + std::to_string(row) +
                              " rows, 'Frames: " + std::to_string(frame_count_) + "'");
  }

  const std::string& text_;
  const std::string& source_;
  size_t pos_ = 0;
  int32_t line_number_ = 0;
  std::vector<RawJoint> joints_;
  std::vector<RawEnd> ends_;
  int32_t channel_count_ = 0;
  int64_t frame_count_ = 0;
  double frame_time_ = 0;
  std::vector<double> values_;
};

struct UnitGuess {
  double scale;
  const char* name;
};

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
  Parser p(text, source);
  p.parse();
  const auto& joints = p.joints_;
  const int32_t n = static_cast<int32_t>(joints.size());
  BvhClip clip;
  BvhConversion& conv = clip.conversion;
  conv.channel_count = p.channel_count_;
  conv.frame_time = p.frame_time_;

  // Rest positions (file units, file axes) of joints and end sites.
  std::vector<Eigen::Vector3d> rest(static_cast<size_t>(n));
  std::vector<Eigen::Vector3d> points;
  for (int32_t j = 0; j < n; ++j) {
    rest[j] = joints[j].offset + (joints[j].parent >= 0 ? rest[joints[j].parent] : Eigen::Vector3d::Zero());
    points.push_back(rest[j]);
  }
  for (const RawEnd& e : p.ends_) points.push_back(rest[e.joint] + e.offset);
  Eigen::Vector3d lo = points[0], hi = points[0];
  for (const auto& x : points) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const Eigen::Vector3d extent = hi - lo;

  // Up axis.
  bool z_up = options.up_axis == BvhUpAxis::kZ;
  if (options.up_axis == BvhUpAxis::kAuto) z_up = extent.z() > extent.y();
  conv.z_up_converted = z_up;
  conv.height_file_units = z_up ? extent.z() : extent.y();

  // Units.
  if (options.scale > 0.0) {
    conv.scale = options.scale;
    conv.unit = "given";
  } else {
    static const UnitGuess kUnits[] = {{1.0, "metre"},       {0.1, "decimetre"},
                                       {0.01, "centimetre"}, {0.001, "millimetre"},
                                       {0.0254, "inch"},     {0.0254 / 0.45, "CMU ASF unit (1/0.45 inch)"}};
    conv.scale_guessed = true;
    const double h = conv.height_file_units;
    if (!(h > 0.0)) {
      conv.scale = 1.0;
      conv.unit = "metre (no height to guess from)";
    } else {
      const UnitGuess* best = &kUnits[0];
      for (const UnitGuess& u : kUnits)
        if (std::abs(std::log(h * u.scale / 1.7)) < std::abs(std::log(h * best->scale / 1.7))) best = &u;
      const double metres = h * best->scale;
      if (metres >= 1.0 && metres <= 2.6) {
        conv.scale = best->scale;
        conv.unit = best->name;
      } else {
        conv.scale = 1.7 / h;
        conv.unit = "fit to 1.7 m";
      }
    }
  }
  conv.height_m = conv.height_file_units * conv.scale;

  // Position channels: absolute (replace OFFSET) or relative (add to it).
  bool relative = options.positions == BvhPositions::kRelative;
  if (options.positions == BvhPositions::kAuto && p.frame_count_ > 0) {
    double value_sum = 0, offset_sum = 0;
    int count = 0;
    for (int32_t j = 1; j < n; ++j)
      for (size_t c = 0; c < joints[j].channels.size(); ++c)
        if (joints[j].channels[c] <= kZpos) {
          value_sum += std::abs(p.values_[static_cast<size_t>(joints[j].first_channel) + c]);
          offset_sum += std::abs(joints[j].offset[joints[j].channels[c]]);
          ++count;
        }
    relative = count > 0 && value_sum < 0.1 * offset_sum;
  }
  for (int32_t j = 1; j < n; ++j)
    for (Channel c : joints[j].channels)
      if (c <= kZpos) {
        ++conv.joints_with_positions;
        break;
      }
  conv.positions_relative = relative;

  // Frame rate.
  double rate = 1.0 / p.frame_time_;
  if (options.snap_frame_rate) {
    const double whole = std::round(rate);
    if (whole >= 1.0 && std::abs(rate - whole) <= 1e-4 * rate && rate != whole) {
      rate = whole;
      conv.frame_rate_snapped = true;
    }
  }

  // Axis change (Z up -> Y up: (x, y, z) -> (x, z, -y)) and scaling.
  const Eigen::Quaterniond axes =
      z_up ? Eigen::Quaterniond(Eigen::AngleAxisd(-90.0 * kDegree, Eigen::Vector3d::UnitX()))
           : Eigen::Quaterniond::Identity();
  const Eigen::Matrix3d axes_m = axes.toRotationMatrix();
  const double s = conv.scale;
  auto point = [&](const Eigen::Vector3d& v) -> Eigen::Vector3d { return s * (axes_m * v); };

  Motion& m = clip.motion;
  Skeleton& sk = m.skeleton;
  sk.names.resize(static_cast<size_t>(n));
  sk.parents.resize(static_cast<size_t>(n));
  sk.rest_translation.resize(n, 3);
  sk.rest_rotation.assign(static_cast<size_t>(n), Eigen::Quaterniond::Identity());
  clip.rotation_orders.resize(static_cast<size_t>(n));
  for (int32_t j = 0; j < n; ++j) {
    sk.names[j] = joints[j].name;
    sk.parents[j] = joints[j].parent;
    sk.rest_translation.row(j) = point(joints[j].offset).transpose();
    for (Channel c : joints[j].channels)
      if (c >= kXrot) clip.rotation_orders[j] += static_cast<char>('X' + (c - kXrot));
  }
  try {
    validate_skeleton(sk, source);  // duplicate joint names
  } catch (const Error& e) {
    fail(PLEAT_ERROR_FORMAT, e.what());
  }
  for (const RawEnd& e : p.ends_) clip.end_sites.push_back({e.joint, point(e.offset)});

  m.frame_rate = rate;
  m.frame_count = p.frame_count_;
  m.rotations.resize(static_cast<size_t>(m.frame_count) * static_cast<size_t>(n));
  m.root_translation.resize(m.frame_count, 3);
  const Eigen::Quaterniond axes_inv = axes.conjugate();
  static const Eigen::Vector3d kAxis[3] = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                           Eigen::Vector3d::UnitZ()};
  for (int64_t f = 0; f < m.frame_count; ++f) {
    const double* row = p.values_.data() + static_cast<size_t>(f) * static_cast<size_t>(p.channel_count_);
    Eigen::Quaterniond* out = m.rotations.data() + f * n;
    for (int32_t j = 0; j < n; ++j) {
      const RawJoint& joint = joints[j];
      Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
      Eigen::Vector3d position = joint.offset;
      bool has_position = false;
      Eigen::Vector3d given = relative ? Eigen::Vector3d::Zero() : joint.offset;
      for (size_t c = 0; c < joint.channels.size(); ++c) {
        const double v = row[static_cast<size_t>(joint.first_channel) + c];
        const Channel ch = joint.channels[c];
        if (ch >= kXrot) {
          q = q * Eigen::Quaterniond(Eigen::AngleAxisd(v * kDegree, kAxis[ch - kXrot]));
        } else {
          given[ch] = v;
          has_position = true;
        }
      }
      if (has_position) position = relative ? Eigen::Vector3d(joint.offset + given) : given;
      q.normalize();
      out[j] = z_up ? (axes * q * axes_inv).normalized() : q;
      if (j == 0) {
        m.root_translation.row(f) = point(position).transpose();
      } else if (has_position) {
        const double deviation = s * (position - joint.offset).norm();
        if (deviation > conv.dropped_translation_m) {
          conv.dropped_translation_m = deviation;
          conv.dropped_translation_joint = joint.name;
        }
      }
    }
  }
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
