#include "body/makehuman_targets.h"

#include <charconv>
#include <cmath>
#include <map>
#include <sstream>
#include <string_view>

#include "body/makehuman.h"
#include "core/error.h"
#include "io/text_file.h"

namespace pleat {

const std::array<const char*, kMakeHumanCategoryCount> kMakeHumanCategories = {"male",
                                                                               "female",
                                                                               "baby",
                                                                               "child",
                                                                               "young",
                                                                               "old",
                                                                               "african",
                                                                               "asian",
                                                                               "caucasian",
                                                                               "minmuscle",
                                                                               "averagemuscle",
                                                                               "maxmuscle",
                                                                               "minweight",
                                                                               "averageweight",
                                                                               "maxweight",
                                                                               "minheight",
                                                                               "maxheight",
                                                                               "idealproportions",
                                                                               "uncommonproportions"};

namespace {

// Splits text into lines (LF or CRLF) and calls fn(line, line_number).
template <typename Fn>
void for_each_line(const std::string& text, Fn fn) {
  size_t at = 0;
  int64_t number = 0;
  while (at < text.size()) {
    size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    size_t stop = end;
    if (stop > at && text[stop - 1] == '\r') --stop;
    fn(std::string_view(text.data() + at, stop - at), ++number);
    at = end + 1;
  }
}

// Parses the next whitespace-separated number of `s` from *pos.
template <typename T>
bool next_number(std::string_view s, size_t* pos, T* value) {
  while (*pos < s.size() && (s[*pos] == ' ' || s[*pos] == '\t')) ++*pos;
  if (*pos >= s.size()) return false;
  const char* b = s.data() + *pos;
  const char* e = s.data() + s.size();
  if (*b == '+') ++b;
  auto r = std::from_chars(b, e, *value);
  if (r.ec != std::errc()) return false;
  *pos = static_cast<size_t>(r.ptr - s.data());
  return true;
}

// The category tokens of a target's file name; folder names (height/,
// proportions/) and "universal" weigh 1.
std::vector<int32_t> tokens_of(const std::string& original, const std::string& where) {
  const size_t slash = original.rfind('/');
  std::string name = original.substr(slash == std::string::npos ? 0 : slash + 1);
  const std::string suffix = ".target";
  if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
    name.resize(name.size() - suffix.size());
  std::vector<int32_t> tokens;
  std::stringstream ss(name);
  std::string token;
  while (std::getline(ss, token, '-')) {
    if (token == "universal") continue;
    size_t k = 0;
    while (k < kMakeHumanCategoryCount && token != kMakeHumanCategories[k]) ++k;
    if (k == kMakeHumanCategoryCount)
      fail(PLEAT_ERROR_FORMAT, where + ": target '" + original + "' has an unknown token '" + token + "'");
    tokens.push_back(static_cast<int32_t>(k));
  }
  return tokens;
}

}  // namespace

std::vector<ShapeParameter> makehuman_shape_parameters() {
  const double third = 1.0 / 3.0;
  return {
      {"gender", 0.5, 0.5, 0.0, 1.0, "0 female .. 1 male"},
      {"age", 0.5, 0.5, 0.0, 1.0, "0 = 1 year, 0.1875 = 10, 0.5 = 25, 1 = 90 years"},
      {"muscle", 0.5, 0.5, 0.0, 1.0, "0 minimum .. 0.5 average .. 1 maximum muscle"},
      {"weight", 0.5, 0.5, 0.0, 1.0, "0 minimum .. 0.5 average .. 1 maximum weight"},
      {"height", 0.5, 0.5, 0.0, 1.0, "0 short .. 0.5 average .. 1 tall"},
      {"proportions", 0.5, 0.5, 0.0, 1.0, "0 uncommon .. 0.5 regular .. 1 ideal body proportions"},
      {"african", third, third, 0.0, 1.0, "ethnic mix (the three are renormalised to sum 1)"},
      {"asian", third, third, 0.0, 1.0, "ethnic mix (the three are renormalised to sum 1)"},
      {"caucasian", third, third, 0.0, 1.0, "ethnic mix (the three are renormalised to sum 1)"},
  };
}

Eigen::VectorXd makehuman_default_beta() {
  Eigen::VectorXd b(kMakeHumanBetaCount);
  const auto p = makehuman_shape_parameters();
  for (int i = 0; i < kMakeHumanBetaCount; ++i) b[i] = p[static_cast<size_t>(i)].default_value;
  return b;
}

std::vector<std::pair<std::string, double>> makehuman_category_values(const Eigen::VectorXd& beta) {
  const auto c = makehuman_categories(beta);
  std::vector<std::pair<std::string, double>> out;
  for (size_t k = 0; k < kMakeHumanCategoryCount; ++k) out.emplace_back(kMakeHumanCategories[k], c[k]);
  return out;
}

std::array<double, kMakeHumanCategoryCount> makehuman_categories(const Eigen::VectorXd& beta) {
  const auto params = makehuman_shape_parameters();
  if (beta.size() != kMakeHumanBetaCount)
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         "makehuman: beta has " + std::to_string(beta.size()) + " entries, expected " +
             std::to_string(kMakeHumanBetaCount) +
             " (gender age muscle weight height proportions african asian caucasian)");
  for (int i = 0; i < kMakeHumanBetaCount; ++i)
    if (!std::isfinite(beta[i]) || beta[i] < 0.0 || beta[i] > 1.0)
      fail(PLEAT_ERROR_INVALID_ARGUMENT, "makehuman: beta[" + std::to_string(i) + "] '" + params[i].name +
                                             "' = " + std::to_string(beta[i]) + " is outside [0, 1]");
  const double g = beta[0], a = beta[1], m = beta[2], w = beta[3], h = beta[4], p = beta[5];
  const double ethnic_sum = beta[6] + beta[7] + beta[8];
  if (ethnic_sum <= 0.0)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "makehuman: the ethnic values (african, asian, caucasian) sum to 0");
  double baby, child, young, old;
  if (a < 0.5) {
    baby = std::max(0.0, 1.0 - a / 0.1875);
    young = std::max(0.0, (a - 0.1875) / 0.3125);
    child = std::max(0.0, std::min(1.0, a / 0.1875) - young);
    old = 0.0;
  } else {
    baby = child = 0.0;
    old = 2.0 * a - 1.0;
    young = 1.0 - old;
  }
  // A slider's three categories: below, at and above its middle.
  auto three = [](double x, double* lo, double* mid, double* hi) {
    *hi = std::max(0.0, 2.0 * x - 1.0);
    *lo = std::max(0.0, 1.0 - 2.0 * x);
    *mid = 1.0 - *hi - *lo;
  };
  double mlo, mmid, mhi, wlo, wmid, whi, unused;
  three(m, &mlo, &mmid, &mhi);
  three(w, &wlo, &wmid, &whi);
  double hlo, hhi, plo, phi;
  three(h, &hlo, &unused, &hhi);
  three(p, &plo, &unused, &phi);  // uncommon = lo, ideal = hi
  return {g,
          1.0 - g,
          baby,
          child,
          young,
          old,
          beta[6] / ethnic_sum,
          beta[7] / ethnic_sum,
          beta[8] / ethnic_sum,
          mlo,
          mmid,
          mhi,
          wlo,
          wmid,
          whi,
          hlo,
          hhi,
          phi,
          plo};
}

MakeHumanTargets::MakeHumanTargets(const std::string& dir, int32_t vertex_count)
    : folder_(dir + "/targets/macrodetails/"), vertex_count_(vertex_count) {
  const std::string path = folder_ + "MANIFEST.tsv";
  const std::string text = read_text_file(path);
  std::map<std::string, int32_t> stored_index;
  for_each_line(text, [&](std::string_view line, int64_t number) {
    if (line.empty() || line[0] == '#') return;
    const std::string where = path + ": line " + std::to_string(number);
    const size_t tab = line.find('\t');
    if (tab == std::string::npos) fail(PLEAT_ERROR_FORMAT, where + ": expected 'original<TAB>stored...'");
    const size_t tab2 = line.find('\t', tab + 1);
    Entry e;
    e.original = std::string(line.substr(0, tab));
    const std::string stored(
        line.substr(tab + 1, tab2 == std::string::npos ? std::string::npos : tab2 - tab - 1));
    if (stored.empty() || stored.find("..") != std::string::npos)
      fail(PLEAT_ERROR_FORMAT, where + ": bad stored file name '" + stored + "'");
    auto it = stored_index.find(stored);
    if (it == stored_index.end()) {
      it = stored_index.emplace(stored, static_cast<int32_t>(stored_files_.size())).first;
      stored_files_.push_back(stored);
    }
    e.stored = it->second;
    e.tokens = tokens_of(e.original, where);
    manifest_.push_back(std::move(e));
  });
  if (manifest_.empty()) fail(PLEAT_ERROR_FORMAT, path + ": lists no targets");
  stored_.resize(stored_files_.size());
}

std::vector<std::pair<std::string, double>> MakeHumanTargets::weights(const Eigen::VectorXd& beta) const {
  const auto c = makehuman_categories(beta);
  std::vector<std::pair<std::string, double>> out;
  for (const Entry& e : manifest_) {
    double w = 1.0;
    for (int32_t t : e.tokens) w *= c[static_cast<size_t>(t)];
    if (w != 0.0) out.emplace_back(e.original, w);
  }
  return out;
}

void MakeHumanTargets::add_to(const Eigen::VectorXd& beta, Points3d* base) {
  const auto c = makehuman_categories(beta);
  std::vector<double> stored_weight(stored_files_.size(), 0.0);
  for (const Entry& e : manifest_) {
    double w = 1.0;
    for (int32_t t : e.tokens) w *= c[static_cast<size_t>(t)];
    stored_weight[static_cast<size_t>(e.stored)] += w;
  }
  for (size_t s = 0; s < stored_weight.size(); ++s) {
    const double w = stored_weight[s];
    if (w == 0.0) continue;
    const Offsets& t = stored(static_cast<int32_t>(s));
    for (size_t k = 0; k < t.index.size(); ++k)
      for (int a = 0; a < 3; ++a)
        (*base)(t.index[k], a) += w * static_cast<double>(t.offset[3 * k + static_cast<size_t>(a)]);
  }
}

const MakeHumanTargets::Offsets& MakeHumanTargets::stored(int32_t i) {
  std::lock_guard<std::mutex> lock(mutex_);
  Offsets& t = stored_[static_cast<size_t>(i)];
  if (t.loaded) return t;
  const std::string path = folder_ + stored_files_[static_cast<size_t>(i)];
  Offsets parsed;  // kept only when the whole file parses
  for_each_line(read_gzip_file(path), [&](std::string_view line, int64_t number) {
    size_t pos = 0;
    while (pos < line.size() && (line[pos] == ' ' || line[pos] == '\t')) ++pos;
    if (pos == line.size() || line[pos] == '#') return;
    const std::string where = path + ": line " + std::to_string(number);
    int32_t v;
    float d[3];
    if (!next_number(line, &pos, &v) || !next_number(line, &pos, &d[0]) || !next_number(line, &pos, &d[1]) ||
        !next_number(line, &pos, &d[2]))
      fail(PLEAT_ERROR_FORMAT, where + " is not 'index dx dy dz'");
    if (v < 0 || v >= vertex_count_)
      fail(PLEAT_ERROR_FORMAT,
           where + " names vertex " + std::to_string(v) + " of " + std::to_string(vertex_count_));
    if (!std::isfinite(d[0]) || !std::isfinite(d[1]) || !std::isfinite(d[2]))
      fail(PLEAT_ERROR_FORMAT, where + " has a non-finite offset");
    parsed.index.push_back(v);
    parsed.offset.insert(parsed.offset.end(), {d[0], d[1], d[2]});
  });
  t = std::move(parsed);
  t.loaded = true;
  return t;
}

}  // namespace pleat
