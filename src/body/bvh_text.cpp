#include "body/bvh_text.h"

#include <charconv>
#include <cmath>
#include <string_view>

#include "core/error.h"

namespace pleat::bvh {
namespace {

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

}  // namespace

RawBvh parse_bvh_text(const std::string& text, const std::string& source) {
  Parser p(text, source);
  p.parse();
  RawBvh raw;
  raw.joints = std::move(p.joints_);
  raw.ends = std::move(p.ends_);
  raw.channel_count = p.channel_count_;
  raw.frame_count = p.frame_count_;
  raw.frame_time = p.frame_time_;
  raw.values = std::move(p.values_);
  return raw;
}

}  // namespace pleat::bvh
