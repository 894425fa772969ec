#include "io/fbx_precheck.h"

#include <cctype>
#include <cstdint>
#include <cstring>
#include <map>
#include <set>
#include <string_view>
#include <vector>

#include "core/error.h"

namespace pleat {
namespace {

constexpr int kMaxDepth = 64;

// The parts of a scene the checks need, read from either encoding.
struct Outline {
  std::set<int64_t> models;                        // ids of `Objects/Model` records
  std::vector<std::pair<int64_t, int64_t>> links;  // `Connections/C: "OO", child, parent`
};

[[noreturn]] void refuse_depth(const std::string& path) {
  fail(PLEAT_ERROR_FORMAT, path + ": FBX scopes nested more than " + std::to_string(kMaxDepth) +
                               " deep; no real scene nests like this");
}

bool parse_id(std::string_view text, int64_t* id) {
  if (text.empty() || text.size() > 20) return false;
  size_t i = text[0] == '-' ? 1 : 0;
  if (i == text.size()) return false;
  int64_t v = 0;
  for (; i < text.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(text[i])) || v > (INT64_MAX - 9) / 10) return false;
    v = v * 10 + (text[i] - '0');
  }
  *id = text[0] == '-' ? -v : v;
  return true;
}

// ASCII FBX, tokenised as assimp does: keys end in ':', data tokens are
// separated by commas, strings are quoted, ';' starts a comment to the end of
// the line, braces open and close a record's children.
class AsciiReader {
 public:
  AsciiReader(const std::string& path, std::string_view text) : path_(path), text_(text) {}

  Outline read() {
    for (size_t i = 0; i < text_.size();) {
      const char c = text_[i];
      if (std::isspace(static_cast<unsigned char>(c))) {
        ++i;
      } else if (c == ';') {
        while (i < text_.size() && text_[i] != '\n') ++i;
      } else if (c == '"') {
        const size_t close = text_.find('"', i + 1);
        const size_t end = close == std::string_view::npos ? text_.size() : close;
        data_.push_back(text_.substr(i + 1, end - i - 1));
        i = end + 1;
      } else if (c == '{') {
        end_record();
        scopes_.push_back(key_);
        if (scopes_.size() > static_cast<size_t>(kMaxDepth)) refuse_depth(path_);
        key_ = {};
        ++i;
      } else if (c == '}') {
        end_record();
        if (!scopes_.empty()) scopes_.pop_back();
        key_ = {};
        ++i;
      } else if (c == ',') {
        ++i;
      } else {
        // Up to the next space or delimiter; a byte that is neither (a NUL)
        // still makes a token, so every step moves on.
        size_t end = i + 1;
        while (end < text_.size() && !std::isspace(static_cast<unsigned char>(text_[end])) &&
               std::string_view("{},;\"").find(text_[end]) == std::string_view::npos)
          ++end;
        const std::string_view token = text_.substr(i, end - i);
        if (token.back() == ':') {
          end_record();
          key_ = token.substr(0, token.size() - 1);
        } else {
          data_.push_back(token);
        }
        i = end;
      }
    }
    end_record();
    return std::move(outline_);
  }

 private:
  void end_record() {
    if (scopes_.size() == 1) {
      int64_t a = 0, b = 0;
      if (scopes_[0] == "Objects" && key_ == "Model" && !data_.empty() && parse_id(data_[0], &a))
        outline_.models.insert(a);
      if (scopes_[0] == "Connections" && key_ == "C" && data_.size() >= 3 && data_[0] == "OO" &&
          parse_id(data_[1], &a) && parse_id(data_[2], &b))
        outline_.links.push_back({a, b});
    }
    data_.clear();
  }

  const std::string& path_;
  std::string_view text_;
  std::vector<std::string_view> scopes_;  // keys of the open records, outermost first
  std::string_view key_;                  // the record being read
  std::vector<std::string_view> data_;    // its data tokens so far
  Outline outline_;
};

// Binary FBX: each record holds its end offset, its property count and
// length, its name, its properties, then nested records up to its end
// (closed by a null record). Walked with an explicit stack.
class BinaryReader {
 public:
  BinaryReader(const std::string& path, std::string_view bytes) : path_(path), bytes_(bytes) {}

  Outline read() {
    constexpr size_t kMagic = 23;
    if (bytes_.size() < kMagic + 4) return {};
    const bool wide = u64(kMagic, 4) >= 7500;  // 64-bit offsets from FBX 7.5
    word_ = wide ? 8 : 4;
    const size_t header = 3 * word_ + 1;
    struct Scope {
      size_t at, end;
      int depth;
      std::string_view parent;  // name of the record whose children these are
    };
    std::vector<Scope> stack = {{kMagic + 4, bytes_.size(), 0, {}}};
    while (!stack.empty()) {
      Scope s = stack.back();
      stack.pop_back();
      while (s.at + header <= s.end) {
        const uint64_t end = u64(s.at, word_), properties = u64(s.at + 2 * word_, word_);
        const size_t name_length = static_cast<unsigned char>(bytes_[s.at + 3 * word_]);
        if (end == 0) break;  // the null record that closes a list
        if (end <= s.at || end > s.end)
          refuse(s.at, "ends at byte " + std::to_string(end) +
                           ", not between its start and its parent's end (byte " + std::to_string(s.end) +
                           ")");
        if (s.at + header + name_length > end) refuse(s.at, "has a name that runs past its end");
        const std::string_view name = bytes_.substr(s.at + header, name_length);
        const size_t first_property = s.at + header + name_length;
        // assimp adds this length to a pointer before comparing, so a length
        // near 2^64 wraps and its tokenizer aborts (found by fuzz_fbx).
        if (properties > end - first_property)
          refuse(s.at, "declares " + std::to_string(properties) + " bytes of properties; it holds " +
                           std::to_string(end - first_property));
        const uint64_t nested = first_property + properties;
        if (s.depth == 1) read_record(s.parent, name, first_property, nested);
        if (nested < end) {
          if (s.depth + 1 > kMaxDepth) refuse_depth(path_);
          stack.push_back({static_cast<size_t>(nested), static_cast<size_t>(end), s.depth + 1, name});
        }
        s.at = static_cast<size_t>(end);
      }
    }
    return std::move(outline_);
  }

 private:
  // Records must lie within their parents and their properties within
  // themselves: assimp 5.2 trusts both.
  [[noreturn]] void refuse(size_t at, const std::string& what) const {
    fail(PLEAT_ERROR_FORMAT, path_ + ": FBX record at byte " + std::to_string(at) + " " + what);
  }

  uint64_t u64(size_t at, size_t width) const {
    uint64_t v = 0;
    std::memcpy(&v, bytes_.data() + at, width);  // little endian, as FBX
    return v;
  }

  // The property at `at` if it is an int64 ('L') within `end`.
  bool int64_property(size_t* at, size_t end, int64_t* value) const {
    if (*at + 9 > end || bytes_[*at] != 'L') return false;
    *value = static_cast<int64_t>(u64(*at + 1, 8));
    *at += 9;
    return true;
  }

  // A record one level below the top: Objects/Model or Connections/C.
  void read_record(std::string_view parent, std::string_view name, size_t at, size_t end) {
    int64_t a = 0, b = 0;
    if (parent == "Objects" && name == "Model" && int64_property(&at, end, &a)) outline_.models.insert(a);
    if (parent != "Connections" || name != "C") return;
    if (at + 5 > end || bytes_[at] != 'S') return;
    const uint64_t length = u64(at + 1, 4);
    if (length != 2 || at + 7 > end || bytes_.substr(at + 5, 2) != "OO") return;
    at += 7;
    if (int64_property(&at, end, &a) && int64_property(&at, end, &b)) outline_.links.push_back({a, b});
  }

  const std::string& path_;
  std::string_view bytes_;
  size_t word_ = 4;
  Outline outline_;
};

// Depth-first search over the model-to-parent-model links; the first model
// reached twice on one path is on a cycle.
void refuse_model_cycles(const std::string& path, const Outline& outline) {
  std::map<int64_t, std::vector<int64_t>> parents;
  for (const auto& [child, parent] : outline.links)
    if (outline.models.count(child) && outline.models.count(parent)) parents[child].push_back(parent);
  enum class Mark { kNone, kOnPath, kDone };
  std::map<int64_t, Mark> mark;
  for (const auto& start : parents) {
    if (mark[start.first] != Mark::kNone) continue;
    std::vector<std::pair<int64_t, size_t>> stack{{start.first, 0}};
    mark[start.first] = Mark::kOnPath;
    while (!stack.empty()) {
      auto& [model, next] = stack.back();
      const auto it = parents.find(model);
      if (it == parents.end() || next == it->second.size()) {
        mark[model] = Mark::kDone;
        stack.pop_back();
        continue;
      }
      const int64_t parent = it->second[next++];
      if (mark[parent] == Mark::kOnPath)
        fail(PLEAT_ERROR_FORMAT, path + ": FBX model " + std::to_string(parent) +
                                     " is its own ancestor (a cycle in the scene's parent links)");
      if (mark[parent] == Mark::kNone) {
        mark[parent] = Mark::kOnPath;
        stack.push_back({parent, 0});
      }
    }
  }
}

}  // namespace

void check_fbx_before_assimp(const std::string& path, const std::string& bytes) {
  const Outline outline = bytes.rfind("Kaydara FBX Binary", 0) == 0 ? BinaryReader(path, bytes).read()
                                                                    : AsciiReader(path, bytes).read();
  refuse_model_cycles(path, outline);
}

}  // namespace pleat
