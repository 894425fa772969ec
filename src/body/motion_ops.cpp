#include "body/motion_ops.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "core/error.h"

namespace pleat {

namespace {

std::string frame_joint(const std::string& source, const Motion& m, int64_t f, int32_t j) {
  return source + ": frame " + std::to_string(f) + ", joint " + std::to_string(j) + " '" +
         m.skeleton.names[j] + "'";
}

Motion empty_like(const Motion& m, int64_t frames) {
  Motion out;
  out.skeleton = m.skeleton;
  out.frame_rate = m.frame_rate;
  out.frame_count = frames;
  out.rotations.resize(static_cast<size_t>(frames) * static_cast<size_t>(m.skeleton.joint_count()));
  out.root_translation.resize(frames, 3);
  return out;
}

// Global rest rotations and positions.
void rest_pose(const Skeleton& s, std::vector<Eigen::Matrix3d>* rotation,
               std::vector<Eigen::Vector3d>* position) {
  const Transforms g = rest_transforms(s);
  rotation->resize(g.size());
  position->resize(g.size());
  for (size_t j = 0; j < g.size(); ++j) {
    (*rotation)[j] = g[j].linear();
    (*position)[j] = g[j].translation();
  }
}

std::vector<std::vector<int32_t>> children_of(const Skeleton& s) {
  std::vector<std::vector<int32_t>> children(static_cast<size_t>(s.joint_count()));
  for (int32_t j = 1; j < s.joint_count(); ++j) children[s.parents[j]].push_back(j);
  return children;
}

// Length of the leg from joint `top` down to joint `bottom` (an ancestor chain)
// in the rest pose, as if straightened vertically: bones within 30 degrees of
// vertical count with their full length, others (pelvis to hip joint, toes)
// with their drop only. Rest legs that splay outwards (CMU: about 20 degrees) then
// measure what they reach once the motion swings them under the body.
double leg_length(const std::vector<Eigen::Vector3d>& p, const std::vector<int32_t>& parents, int32_t top,
                  int32_t bottom) {
  double length = 0.0;
  for (int32_t j = bottom; j != top && j > 0; j = parents[j]) {
    const Eigen::Vector3d d = p[j] - p[parents[j]];
    const double drop = -d.y();
    // Within 30 degrees of vertical: a leg bone (CMU legs splay by ~20).
    length += std::abs(drop) >= 0.8660254 * d.norm() ? (drop >= 0 ? d.norm() : -d.norm()) : drop;
  }
  return length;
}

}  // namespace

void validate_motion(const Motion& m, const std::string& source) {
  validate_skeleton(m.skeleton, source);
  const int32_t n = m.skeleton.joint_count();
  if (!std::isfinite(m.frame_rate) || !(m.frame_rate > 0.0))
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         source + ": frame rate " + std::to_string(m.frame_rate) + " is not > 0");
  if (m.frame_count < 0 ||
      m.rotations.size() != static_cast<size_t>(m.frame_count) * static_cast<size_t>(n) ||
      m.root_translation.rows() != m.frame_count)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, source + ": motion arrays disagree with " +
                                           std::to_string(m.frame_count) + " frames of " + std::to_string(n) +
                                           " joints (" + std::to_string(m.rotations.size()) + " rotations, " +
                                           std::to_string(m.root_translation.rows()) + " root positions)");
  for (int64_t f = 0; f < m.frame_count; ++f) {
    const Eigen::Quaterniond* q = m.frame(f);
    for (int32_t j = 0; j < n; ++j)
      if (!q[j].coeffs().allFinite() || std::abs(q[j].norm() - 1.0) > 1e-6)
        fail(PLEAT_ERROR_INVALID_ARGUMENT,
             frame_joint(source, m, f, j) + ": rotation is not a finite unit quaternion");
    if (!m.root_translation.row(f).allFinite())
      fail(PLEAT_ERROR_INVALID_ARGUMENT,
           source + ": frame " + std::to_string(f) + ": root translation is not finite");
  }
}

Points3d joint_positions(const Motion& m, int64_t frame) {
  if (frame < 0 || frame >= m.frame_count)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "joint_positions: frame " + std::to_string(frame) + " outside [0, " +
                                           std::to_string(m.frame_count) + ")");
  Transforms g;
  forward_kinematics(m.skeleton, m.frame(frame), m.root_translation.row(frame).transpose(), &g);
  Points3d p(m.skeleton.joint_count(), 3);
  for (size_t j = 0; j < g.size(); ++j) p.row(static_cast<Eigen::Index>(j)) = g[j].translation().transpose();
  return p;
}

Motion resample_motion(const Motion& m, double frame_rate) {
  if (!std::isfinite(frame_rate) || !(frame_rate > 0.0))
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         "resample_motion: target frame rate " + std::to_string(frame_rate) + " is not finite and > 0");
  validate_motion(m, "resample_motion");
  if (m.frame_count == 0) {
    Motion out = empty_like(m, 0);
    out.frame_rate = frame_rate;
    return out;
  }
  const double duration = static_cast<double>(m.frame_count - 1) / m.frame_rate;
  // The epsilon keeps 565/120 * 30 = 141.25 and exact multiples from rounding down.
  const int64_t frames = static_cast<int64_t>(std::floor(duration * frame_rate + 1e-9)) + 1;
  Motion out = empty_like(m, frames);
  out.frame_rate = frame_rate;
  const int32_t n = m.skeleton.joint_count();
  for (int64_t i = 0; i < frames; ++i) {
    const double u = static_cast<double>(i) * m.frame_rate / frame_rate;  // source frame position
    int64_t f0 = static_cast<int64_t>(std::floor(u + 1e-9));
    f0 = std::clamp<int64_t>(f0, 0, m.frame_count - 1);
    double t = u - static_cast<double>(f0);
    if (std::abs(t) < 1e-9 || f0 == m.frame_count - 1) t = 0.0;
    const int64_t f1 = std::min(f0 + 1, m.frame_count - 1);
    const Eigen::Quaterniond* a = m.frame(f0);
    const Eigen::Quaterniond* b = m.frame(f1);
    Eigen::Quaterniond* q = out.rotations.data() + i * n;
    for (int32_t j = 0; j < n; ++j) q[j] = t == 0.0 ? a[j] : a[j].slerp(t, b[j]).normalized();
    out.root_translation.row(i) =
        t == 0.0
            ? Eigen::RowVector3d(m.root_translation.row(f0))
            : Eigen::RowVector3d((1.0 - t) * m.root_translation.row(f0) + t * m.root_translation.row(f1));
  }
  return out;
}

Motion cut_motion(const Motion& m, int64_t first, int64_t count) {
  if (first < 0 || count < 0 || first + count > m.frame_count)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "cut_motion: frames [" + std::to_string(first) + ", " +
                                           std::to_string(first + count) + ") outside [0, " +
                                           std::to_string(m.frame_count) + ")");
  Motion out = empty_like(m, count);
  const size_t n = static_cast<size_t>(m.skeleton.joint_count());
  std::copy(m.rotations.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(first) * n),
            m.rotations.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(first + count) * n),
            out.rotations.begin());
  out.root_translation = m.root_translation.middleRows(first, count);
  return out;
}

Motion hold_motion(const Motion& m, int64_t frames) {
  if (m.frame_count < 1 || frames < 0)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "hold_motion: " + std::to_string(frames) +
                                           " frames after a motion of " + std::to_string(m.frame_count));
  Motion out = empty_like(m, m.frame_count + frames);
  const size_t n = static_cast<size_t>(m.skeleton.joint_count());
  std::copy(m.rotations.begin(), m.rotations.end(), out.rotations.begin());
  out.root_translation.topRows(m.frame_count) = m.root_translation;
  for (int64_t f = m.frame_count; f < out.frame_count; ++f) {
    std::copy(m.rotations.end() - static_cast<std::ptrdiff_t>(n), m.rotations.end(),
              out.rotations.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(f) * n));
    out.root_translation.row(f) = m.root_translation.row(m.frame_count - 1);
  }
  return out;
}

// ---- Mapping files ---------------------------------------------------------------

JointMap parse_joint_map(const std::string& text, const std::string& source) {
  JointMap map;
  map.source = source;
  std::istringstream in(text);
  std::string line;
  int32_t number = 0;
  std::unordered_map<std::string, int32_t> target_line;
  while (std::getline(in, line)) {
    ++number;
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    std::vector<std::string> tokens;
    for (std::string t; fields >> t;) tokens.push_back(t);
    if (tokens.empty()) continue;
    const std::string where = source + ":" + std::to_string(number) + ": ";
    if (tokens.size() != 2)
      fail(PLEAT_ERROR_FORMAT, where + "expected '<source name>[|<alternative>...] <target name>', found " +
                                   std::to_string(tokens.size()) + " fields");
    JointMapEntry entry;
    entry.line = number;
    entry.target = tokens[1];
    size_t start = 0;
    for (;;) {
      const size_t bar = tokens[0].find('|', start);
      const std::string name =
          tokens[0].substr(start, bar == std::string::npos ? std::string::npos : bar - start);
      if (name.empty()) fail(PLEAT_ERROR_FORMAT, where + "empty source name in '" + tokens[0] + "'");
      entry.sources.push_back(name);
      if (bar == std::string::npos) break;
      start = bar + 1;
    }
    const auto [it, inserted] = target_line.emplace(entry.target, number);
    if (!inserted)
      fail(PLEAT_ERROR_FORMAT, where + "target joint '" + entry.target + "' already mapped on line " +
                                   std::to_string(it->second));
    map.entries.push_back(std::move(entry));
  }
  return map;
}

JointMap read_joint_map(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(PLEAT_ERROR_IO, path + ": cannot open joint map");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_joint_map(text.str(), path);
}

void rename_joints(Skeleton* s, const JointMap& map) {
  for (const JointMapEntry& e : map.entries)
    for (const std::string& name : e.sources) {
      const int32_t j = s->find(name);
      if (j >= 0) {
        s->names[j] = e.target;
        break;
      }
    }
  std::unordered_set<std::string> seen;
  for (const std::string& name : s->names)
    if (!seen.insert(name).second)
      fail(PLEAT_ERROR_INVALID_ARGUMENT, map.source + ": renaming gives two joints named '" + name + "'");
}

// ---- Retargeting ------------------------------------------------------------------

double hip_height(const Skeleton& s) {
  std::vector<Eigen::Matrix3d> r;
  std::vector<Eigen::Vector3d> p;
  rest_pose(s, &r, &p);
  int32_t low = 0;
  for (int32_t j = 0; j < s.joint_count(); ++j)
    if (p[j].y() < p[low].y()) low = j;
  return leg_length(p, s.parents, 0, low);
}

namespace {

// The source joint of every target joint (-1: none): the map's lines first
// (the first of a line's sources the source skeleton has), then equal names
// for target joints the map does not name.
std::vector<int32_t> pair_joints(const Skeleton& ss, const Skeleton& target, const RetargetOptions& options,
                                 RetargetReport* rep) {
  const int32_t nt = target.joint_count();
  std::vector<int32_t> pair(static_cast<size_t>(nt), -1);
  std::vector<bool> target_named(static_cast<size_t>(nt), false);
  std::vector<bool> source_used(static_cast<size_t>(ss.joint_count()), false);
  if (options.map) {
    for (const JointMapEntry& e : options.map->entries) {
      const std::string where = options.map->source + ":" + std::to_string(e.line) + ": ";
      const int32_t t = target.find(e.target);
      if (t < 0) {
        if (options.missing_target == MissingJoint::kError)
          fail(PLEAT_ERROR_INVALID_ARGUMENT,
               where + "target joint '" + e.target + "' is not in the target skeleton");
        rep->skipped_lines.push_back(where + "no target joint '" + e.target + "'");
        continue;
      }
      target_named[t] = true;
      int32_t s = -1;
      for (const std::string& name : e.sources)
        if ((s = ss.find(name)) >= 0) break;
      if (s < 0) {
        std::string names;
        for (const std::string& name : e.sources) names += (names.empty() ? "'" : " or '") + name + "'";
        if (options.missing_source == MissingJoint::kError)
          fail(PLEAT_ERROR_INVALID_ARGUMENT,
               where + "source joint " + names + " is not in the source skeleton");
        rep->skipped_lines.push_back(where + "no source joint " + names);
        continue;
      }
      pair[t] = s;
      source_used[s] = true;
    }
  }
  if (!options.map || options.match_equal_names)
    for (int32_t t = 0; t < nt; ++t) {
      if (target_named[t]) continue;
      const int32_t s = ss.find(target.names[t]);
      if (s >= 0 && !source_used[s]) pair[t] = s;
    }
  if (pair[0] < 0)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "retarget: the target root '" + target.names[0] +
                                           "' has no source joint (map it, e.g. '<source root> " +
                                           target.names[0] + "')");
  return pair;
}

// Per target joint, the rotation that turns its rest direction towards its
// paired children into the source's (inherited from the nearest paired
// ancestor where it has none): bones of different rest poses line up.
std::vector<Eigen::Matrix3d> rest_alignment(const Skeleton& target, const std::vector<int32_t>& pair,
                                            const std::vector<Eigen::Vector3d>& ps,
                                            const std::vector<Eigen::Vector3d>& pt) {
  const int32_t nt = target.joint_count();
  const auto children = children_of(target);
  const double eps = 1e-9 * std::max(1.0, hip_height(target));
  std::vector<Eigen::Matrix3d> align(static_cast<size_t>(nt), Eigen::Matrix3d::Identity());
  std::vector<int32_t> stack;
  for (int32_t t = 0; t < nt; ++t) {
    int32_t ancestor = target.parents[t];
    while (ancestor >= 0 && pair[ancestor] < 0) ancestor = target.parents[ancestor];
    align[t] = ancestor >= 0 ? align[ancestor] : Eigen::Matrix3d::Identity();
    if (pair[t] < 0 || t == 0) continue;
    Eigen::Vector3d vt = Eigen::Vector3d::Zero(), vs = Eigen::Vector3d::Zero();
    stack.assign(children[t].begin(), children[t].end());
    while (!stack.empty()) {
      const int32_t c = stack.back();
      stack.pop_back();
      if (pair[c] >= 0 && (pt[c] - pt[t]).norm() > eps) {
        vt += pt[c] - pt[t];
        vs += ps[pair[c]] - ps[pair[t]];
      } else {
        stack.insert(stack.end(), children[c].begin(), children[c].end());
      }
    }
    if (vt.norm() > eps && vs.norm() > 1e-12 * std::max(1.0, vs.norm()))
      align[t] = Eigen::Quaterniond::FromTwoVectors(vt, vs).toRotationMatrix();
  }
  return align;
}

// Root scale: the ratio of leg lengths, from the paired root down the chain
// to the lowest paired joint (see leg_length), unless the caller gives one.
void choose_root_scale(const Skeleton& ss, const Skeleton& target, const std::vector<int32_t>& pair,
                       const std::vector<Eigen::Vector3d>& ps, const std::vector<Eigen::Vector3d>& pt,
                       double given, RetargetReport* rep) {
  int32_t low = 0;
  for (int32_t t = 0; t < target.joint_count(); ++t)
    if (pair[t] >= 0 && pt[t].y() < pt[low].y()) low = t;
  rep->target_hip_height = leg_length(pt, target.parents, 0, low);
  rep->source_hip_height = leg_length(ps, ss.parents, pair[0], pair[low]);
  if (given > 0.0)
    rep->root_scale = given;
  else if (rep->source_hip_height > 1e-9 && rep->target_hip_height > 1e-9)
    rep->root_scale = rep->target_hip_height / rep->source_hip_height;
  else
    rep->root_scale = 1.0;
}

}  // namespace

Motion retarget_motion(const Motion& source, const Skeleton& target, const RetargetOptions& options,
                       RetargetReport* report) {
  validate_motion(source, "retarget source");
  validate_skeleton(target, "retarget target");
  const Skeleton& ss = source.skeleton;
  const int32_t nt = target.joint_count();
  const int32_t ns = ss.joint_count();
  RetargetReport local_report;
  RetargetReport& rep = report ? *report : local_report;
  rep = RetargetReport();

  const std::vector<int32_t> pair = pair_joints(ss, target, options, &rep);
  std::vector<Eigen::Matrix3d> rs, rt;
  std::vector<Eigen::Vector3d> ps, pt;
  rest_pose(ss, &rs, &ps);
  rest_pose(target, &rt, &pt);
  const std::vector<Eigen::Matrix3d> align = rest_alignment(target, pair, ps, pt);
  choose_root_scale(ss, target, pair, ps, pt, options.root_scale, &rep);
  rep.source_of_target = pair;
  for (int32_t t = 0; t < nt; ++t)
    if (pair[t] < 0) rep.unmapped_targets.push_back(target.names[t]);

  // Frames: each paired joint takes its source's global rotation change
  // since rest, applied to its aligned rest; unpaired joints stay at rest.
  Motion out;
  out.skeleton = target;
  out.frame_rate = source.frame_rate;
  out.frame_count = source.frame_count;
  out.rotations.resize(static_cast<size_t>(source.frame_count) * static_cast<size_t>(nt));
  out.root_translation.resize(source.frame_count, 3);
  Transforms gs;
  std::vector<Eigen::Matrix3d> gt(static_cast<size_t>(nt));
  std::vector<Eigen::Matrix3d> offset(static_cast<size_t>(nt));  // A_t * G_t(rest)
  std::vector<Eigen::Matrix3d> rest_inv_s(static_cast<size_t>(ns));
  for (int32_t t = 0; t < nt; ++t) offset[t] = align[t] * rt[t];
  for (int32_t s = 0; s < ns; ++s) rest_inv_s[s] = rs[s].transpose();
  for (int64_t f = 0; f < source.frame_count; ++f) {
    forward_kinematics(ss, source.frame(f), source.root_translation.row(f).transpose(), &gs);
    Eigen::Quaterniond* q = out.rotations.data() + f * nt;
    for (int32_t t = 0; t < nt; ++t) {
      const Eigen::Matrix3d parent_rest = (t == 0 ? Eigen::Matrix3d::Identity() : gt[target.parents[t]]) *
                                          target.rest_rotation[t].toRotationMatrix();
      if (pair[t] < 0) {
        gt[t] = parent_rest;
        q[t] = Eigen::Quaterniond::Identity();
        continue;
      }
      gt[t] = gs[pair[t]].linear() * rest_inv_s[pair[t]] * offset[t];
      q[t] = Eigen::Quaterniond(parent_rest.transpose() * gt[t]).normalized();
    }
    out.root_translation.row(f) = rep.root_scale * gs[pair[0]].translation().transpose();
  }
  return out;
}

// ---- Mirroring ------------------------------------------------------------------------

std::string mirror_joint_name(const std::string& name) {
  static const std::pair<const char*, const char*> kWords[] = {
      {"Left", "Right"}, {"left", "right"}, {"LEFT", "RIGHT"}};
  for (const auto& [a, b] : kWords) {
    for (const auto& [from, to] : {std::pair<std::string, std::string>{a, b}, {b, a}}) {
      const size_t at = name.find(from);
      if (at != std::string::npos) return name.substr(0, at) + to + name.substr(at + from.size());
    }
  }
  const size_t n = name.size();
  if (n >= 3 && (name[n - 2] == '.' || name[n - 2] == '_')) {
    const char c = name[n - 1];
    const char swapped = c == 'L' ? 'R' : c == 'R' ? 'L' : c == 'l' ? 'r' : c == 'r' ? 'l' : 0;
    if (swapped) return name.substr(0, n - 1) + swapped;
  }
  if (n >= 2 && std::isupper(static_cast<unsigned char>(name[1]))) {
    const char c = name[0];
    const char swapped = c == 'L' ? 'R' : c == 'R' ? 'L' : c == 'l' ? 'r' : c == 'r' ? 'l' : 0;
    if (swapped) return swapped + name.substr(1);
  }
  return name;
}

Motion mirror_motion(const Motion& m) {
  validate_motion(m, "mirror_motion");
  const Skeleton& s = m.skeleton;
  const int32_t n = s.joint_count();
  std::vector<int32_t> partner(static_cast<size_t>(n));
  for (int32_t j = 0; j < n; ++j) {
    const int32_t p = s.find(mirror_joint_name(s.names[j]));
    partner[j] = p >= 0 ? p : j;
  }
  Motion out = empty_like(m, m.frame_count);
  for (int64_t f = 0; f < m.frame_count; ++f) {
    const Eigen::Quaterniond* a = m.frame(f);
    Eigen::Quaterniond* b = out.rotations.data() + f * n;
    for (int32_t j = 0; j < n; ++j) {
      const Eigen::Quaterniond& q = a[partner[j]];
      // Reflection x -> -x conjugates a rotation: axis (x, y, z) -> (x, -y, -z).
      b[j] = Eigen::Quaterniond(q.w(), q.x(), -q.y(), -q.z());
    }
    out.root_translation(f, 0) = -m.root_translation(f, 0);
    out.root_translation(f, 1) = m.root_translation(f, 1);
    out.root_translation(f, 2) = m.root_translation(f, 2);
  }
  return out;
}

Motion turn_motion(const Motion& m, double degrees_per_second, int64_t ease_from, int64_t ease_frames) {
  if (!std::isfinite(degrees_per_second) || ease_from < 0 || ease_frames < 0)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "turn_motion: rate " + std::to_string(degrees_per_second) +
                                           " deg/s, easing from frame " + std::to_string(ease_from) +
                                           " over " + std::to_string(ease_frames) + " frames");
  validate_motion(m, "turn_motion");
  const int32_t n = m.skeleton.joint_count();
  const Eigen::Quaterniond rest = m.skeleton.rest_rotation[0];
  const double step = degrees_per_second * M_PI / 180.0 / m.frame_rate;
  Motion out = m;
  double theta = 0.0;
  for (int64_t f = 0; f < m.frame_count; ++f) {
    if (f > ease_from) {
      const double u = ease_frames == 0 ? 1.0 : std::min(1.0, double(f - ease_from) / double(ease_frames));
      theta += step * u * u * (3.0 - 2.0 * u);
    }
    const Eigen::Quaterniond turn(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()));
    // Global root = rest * pose: turning it in the world is a change of pose
    // seen through the rest orientation.
    out.rotations[static_cast<size_t>(f * n)] = (rest.conjugate() * turn * rest * m.frame(f)[0]).normalized();
    if (f > 0) {
      const Eigen::Vector3d moved = (m.root_translation.row(f) - m.root_translation.row(f - 1)).transpose();
      out.root_translation.row(f) = out.root_translation.row(f - 1) + (turn * moved).transpose();
    }
  }
  return out;
}

}  // namespace pleat
