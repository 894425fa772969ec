#include "plan.h"

#include <cstdio>
#include <set>

#include "capi/pleat.h"
#include "core/error.h"

namespace pleat::datagen {

std::vector<Segment> clip_segments(const Config& config, size_t motion, int64_t frames) {
  const int64_t length = config.segment_frames;
  std::vector<Segment> out;
  if (frames < length) {
    if (frames >= config.min_segment_frames) out.push_back({motion, 0, frames, false});
  } else {
    const int64_t n = std::min(config.segments_per_clip, frames / length);
    // Evenly spread starts: the first at 0, the last ending at the clip's end.
    for (int64_t s = 0; s < n; ++s) {
      const int64_t first = n == 1 ? 0 : s * (frames - length) / (n - 1);
      out.push_back({motion, first, length, false});
    }
  }
  if (config.mirror) {
    const size_t plain = out.size();
    for (size_t i = 0; i < plain; ++i) {
      Segment m = out[i];
      m.mirrored = true;
      out.push_back(m);
    }
  }
  return out;
}

std::vector<Job> plan_jobs(const Config& config, const std::vector<int64_t>& motion_frames) {
  std::vector<Job> jobs;
  std::set<std::string> names;
  const auto name_of = [&](size_t garment, size_t shape, const Segment& s) {
    char first[32];
    std::snprintf(first, sizeof first, "%04lld", static_cast<long long>(s.first));
    return config.garments[garment].name + "-" + config.shapes[shape].name + "-" +
           config.motions[s.motion].name + "-" + first + (s.mirrored ? "m" : "");
  };
  const auto draw = [&](const std::string& split, bool held_out, int64_t wanted) {
    // The pool interleaves the clips (every clip's first segment, then every
    // clip's second, ...), so that a split's first sequences differ in motion.
    std::vector<std::vector<Segment>> per_clip;
    for (size_t m = 0; m < config.motions.size(); ++m) {
      const std::string& ms = config.motions[m].split;
      if (held_out ? ms == "validation" : ms != split) continue;
      per_clip.push_back(clip_segments(config, m, motion_frames[m]));
    }
    std::vector<Segment> pool;
    for (size_t rank = 0, added = 1; added > 0; ++rank) {
      added = 0;
      for (const std::vector<Segment>& segments : per_clip)
        if (rank < segments.size()) {
          pool.push_back(segments[rank]);
          ++added;
        }
    }
    // Every garment x shape pair once, by diagonals: pair (k-th garment, shape
    // (k + d) mod B) for d = 0, 1, ..., so the first pairs of a short split
    // already differ in garment and in shape.
    std::vector<size_t> garments;
    for (size_t g = 0; g < config.garments.size(); ++g)
      if (config.garments[g].held_out == held_out) garments.push_back(g);
    std::vector<std::pair<size_t, size_t>> pairs;  // garment, shape
    const size_t shapes = config.shapes.size();
    for (size_t d = 0; d < shapes; ++d)
      for (size_t k = 0; k < garments.size(); ++k) pairs.emplace_back(garments[k], (k + d) % shapes);
    if (wanted == 0) return;
    if (pool.empty())
      fail(PLEAT_ERROR_INVALID_ARGUMENT,
           "datagen config '" + config.path + "': the " + (held_out ? std::string("held_out") : split) +
               " clips give no segment of at least " + std::to_string(config.min_segment_frames) + " frames");
    // Sequence i takes pair i mod P and segment (i + i / P) mod S: with that
    // shift a pair meets new segments on every round even when P divides S.
    // The stride can cycle through part of the pool only (with one pair it is
    // 2i mod S), so a second pass takes the combinations it missed, in order;
    // plans the first pass fills alone are unchanged.
    const int64_t combinations = static_cast<int64_t>(pairs.size() * pool.size());
    const int64_t p = static_cast<int64_t>(pairs.size()), s = static_cast<int64_t>(pool.size());
    const int64_t target = std::min(wanted, combinations);
    int64_t made = 0;
    const auto take = [&](size_t pair, size_t segment) {
      const auto [g, b] = pairs[pair];
      const Segment& seg = pool[segment];
      const std::string name = name_of(g, b, seg);
      if (!names.insert(name).second) return;
      jobs.push_back({name, held_out ? "test" : split, held_out, "", g, b, seg});
      ++made;
    };
    for (int64_t i = 0; made < target && i < combinations * 2; ++i)
      take(static_cast<size_t>(i % p), static_cast<size_t>((i + i / p) % s));
    for (int64_t i = 0; made < target && i < combinations; ++i)
      take(static_cast<size_t>(i % p), static_cast<size_t>(i / p));
  };
  draw("train", false, config.train);
  draw("validation", false, config.validation);
  draw("test", false, config.test);
  draw("test", true, config.held_out);
  if (!config.twins.split.empty()) {
    const size_t planned = jobs.size();
    for (size_t i = 0; i < planned; ++i)
      if (jobs[i].split == config.twins.split) {
        Job twin = jobs[i];
        twin.name += ".twin";
        twin.twin_of = jobs[i].name;
        jobs.push_back(twin);
      }
  }
  return jobs;
}

}  // namespace pleat::datagen
