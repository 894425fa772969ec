#pragma once
// Reading the JSON configs of pleat-datagen (datagen and import-sequences):
// every access names the file and field on failure.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "core/error.h"

namespace pleat::datagen {

using Json = nlohmann::json;
namespace fs = std::filesystem;

// One JSON object being read: every access names the field on failure, and
// done() refuses keys that were never asked for (typos do not pass silently).
class Fields {
 public:
  Fields(const Json& j, std::string source, std::string where, std::string kind = "datagen config")
      : j_(j), source_(std::move(source)), where_(std::move(where)), kind_(std::move(kind)) {
    if (!j_.is_object()) bad("must be an object");
  }
  [[noreturn]] void bad(const std::string& what, const std::string& key = "") const {
    const std::string field = where_.empty() ? key : (key.empty() ? where_ : where_ + "." + key);
    fail(PLEAT_ERROR_FORMAT,
         kind_ + " '" + source_ + "': " + (field.empty() ? "" : "'" + field + "' ") + what);
  }
  bool has(const std::string& key) const { return j_.contains(key); }
  const Json& at(const std::string& key) {
    used_.insert(key);
    if (!j_.contains(key)) bad("is missing", key);
    return j_.at(key);
  }
  std::string text(const std::string& key, const std::string& fallback = "", bool required = false) {
    if (!has(key) && !required) return fallback;
    const Json& v = at(key);
    if (!v.is_string() || v.get<std::string>().empty()) bad("must be a non-empty string", key);
    return v.get<std::string>();
  }
  double number(const std::string& key, double fallback, double lo, double hi) {
    if (!has(key)) return fallback;
    const Json& v = at(key);
    if (!v.is_number()) bad("must be a number", key);
    const double x = v.get<double>();
    if (!(x >= lo && x <= hi)) bad("must be in [" + fmt(lo) + ", " + fmt(hi) + "], is " + fmt(x), key);
    return x;
  }
  int64_t integer(const std::string& key, int64_t fallback, int64_t lo, int64_t hi) {
    if (!has(key)) return fallback;
    const Json& v = at(key);
    if (!v.is_number_integer()) bad("must be an integer", key);
    const auto x = v.get<int64_t>();
    if (x < lo || x > hi) bad("must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", key);
    return x;
  }
  bool flag(const std::string& key, bool fallback) {
    if (!has(key)) return fallback;
    const Json& v = at(key);
    if (!v.is_boolean()) bad("must be true or false", key);
    return v.get<bool>();
  }
  Fields object(const std::string& key) { return Fields(at(key), source_, join(key), kind_); }
  const Json& list(const std::string& key) {
    const Json& v = at(key);
    if (!v.is_array() || v.empty()) bad("must be a non-empty list", key);
    return v;
  }
  std::string join(const std::string& key) const { return where_.empty() ? key : where_ + "." + key; }
  const std::string& source() const { return source_; }
  void done() const {
    for (const auto& [key, value] : j_.items())
      if (!used_.count(key)) bad("is not a known setting", key);
  }

 private:
  static std::string fmt(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
  }
  const Json& j_;
  std::string source_, where_, kind_;
  std::set<std::string> used_;
};

inline std::string resolve(const fs::path& base, const std::string& p) {
  return fs::path(p).is_absolute() ? p : (base / p).lexically_normal().string();
}

}  // namespace pleat::datagen
