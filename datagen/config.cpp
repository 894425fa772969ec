#include "config.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "capi/pleat.h"
#include "config_fields.h"
#include "core/error.h"
#include "io/sequence.h"

namespace pleat::datagen {
namespace {

void read_cloth(Fields f, ClothSettings* c) {
  c->quality = static_cast<int>(f.integer("quality", c->quality, 1, 80));
  c->mass = f.number("mass", c->mass, 1e-4, 10);
  c->air_damping = f.number("air_damping", c->air_damping, 0, 10);
  c->tension_stiffness = f.number("tension_stiffness", c->tension_stiffness, 0, 10000);
  c->compression_stiffness = f.number("compression_stiffness", c->compression_stiffness, 0, 10000);
  c->shear_stiffness = f.number("shear_stiffness", c->shear_stiffness, 0, 10000);
  c->bending_stiffness = f.number("bending_stiffness", c->bending_stiffness, 0, 10000);
  c->tension_damping = f.number("tension_damping", c->tension_damping, 0, 50);
  c->compression_damping = f.number("compression_damping", c->compression_damping, 0, 50);
  c->shear_damping = f.number("shear_damping", c->shear_damping, 0, 50);
  c->bending_damping = f.number("bending_damping", c->bending_damping, 0, 1000);
  c->pin_stiffness = f.number("pin_stiffness", c->pin_stiffness, 0, 50);
  f.done();
}

void read_collision(Fields f, CollisionSettings* c) {
  c->quality = static_cast<int>(f.integer("quality", c->quality, 1, 20));
  c->distance = f.number("distance", c->distance, 0.001, 1);
  c->body_thickness = f.number("body_thickness", c->body_thickness, 0.001, 1);
  c->body_thickness_inner = f.number("body_thickness_inner", c->body_thickness_inner, 0.001, 1);
  c->friction = f.number("friction", c->friction, 0, 80);
  c->damping = f.number("damping", c->damping, 0, 1);
  c->self_collision = f.flag("self_collision", c->self_collision);
  c->self_distance = f.number("self_distance", c->self_distance, 0.001, 0.1);
  c->self_friction = f.number("self_friction", c->self_friction, 0, 80);
  f.done();
}

void read_check(Fields f, CheckSettings* c) {
  c->max_distance = f.number("max_distance", c->max_distance, 0.01, 10);
  c->max_penetration = f.number("max_penetration", c->max_penetration, 0.001, 1);
  c->max_penetrating_fraction = f.number("max_penetrating_fraction", c->max_penetrating_fraction, 0, 1);
  c->max_body_speed = f.number("max_body_speed", c->max_body_speed, 0.1, 1000);
  c->slip_distance = f.number("slip_distance", c->slip_distance, 0.01, 10);
  c->max_slipped_fraction = f.number("max_slipped_fraction", c->max_slipped_fraction, 0, 1);
  f.done();
}

template <typename Spec>
void require_unique(const std::vector<Spec>& specs, const Fields& f, const std::string& list) {
  std::set<std::string> seen;
  for (size_t i = 0; i < specs.size(); ++i)
    if (!seen.insert(specs[i].name).second)
      f.bad("repeats the name '" + specs[i].name + "'", list + "[" + std::to_string(i) + "]");
}

// A non-empty list of objects read by `read` (which names fields through its
// Fields), with unknown keys refused and names unique.
template <typename Spec, typename Read>
std::vector<Spec> read_list(Fields& f, const std::string& key, Read&& read) {
  const Json& list = f.list(key);
  std::vector<Spec> out;
  for (size_t i = 0; i < list.size(); ++i) {
    Fields item(list[i], f.source(), f.join(key + "[" + std::to_string(i) + "]"));
    out.push_back(read(item));
    item.done();
  }
  require_unique(out, f, key);
  return out;
}

void require_file(const Fields& f, const std::string& path, const std::string& key) {
  if (!fs::is_regular_file(path)) f.bad("names '" + path + "', which is not a file", key);
}

// Names become folder names: keep them to a portable set.
std::string checked_name(Fields& f, const std::string& key, const std::string& fallback) {
  const std::string name = f.text(key, fallback, fallback.empty());
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '+' || c == '-'))
      f.bad("'" + name + "' may hold only letters, digits, '_', '.', '+' and '-'", key);
  return name;
}

}  // namespace

Config parse_config(const std::string& text, const std::string& path) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::exception& e) {
    fail(PLEAT_ERROR_FORMAT, "datagen config '" + path + "': not valid JSON: " + e.what());
  }
  Fields f(j, path, "");
  Config c;
  c.path = path;
  const fs::path base = fs::absolute(fs::path(path)).parent_path();
  const fs::path assets = resolve(base, f.text("assets", "."));
  c.name = checked_name(f, "name", "");
  if (f.has("output")) c.output = resolve(base, f.text("output"));
  c.blender = f.text("blender", c.blender);
  c.body = resolve(assets, f.text("body", "", true));
  if (!fs::is_regular_file(fs::path(c.body) / "base.obj"))
    f.bad("names '" + c.body + "', which holds no MakeHuman base.obj", "body");
  if (f.has("collider")) {
    c.collider = resolve(assets, f.text("collider"));
    require_file(f, c.collider, "collider");
  }
  c.rig = f.text("rig", c.rig);
  if (c.rig != "cmu_mb" && c.rig != "default") f.bad("must be \"cmu_mb\" or \"default\"", "rig");
  c.frame_rate = f.number("frame_rate", c.frame_rate, 1, 1000);
  c.segment_frames = f.integer("segment_frames", c.segment_frames, 2, 100000);
  c.segments_per_clip = f.integer("segments_per_clip", c.segments_per_clip, 1, 1000);
  c.min_segment_frames =
      f.integer("min_segment_frames", std::min(c.min_segment_frames, c.segment_frames), 2, c.segment_frames);
  c.mirror = f.flag("mirror", c.mirror);
  c.rest_frames = f.integer("rest_frames", c.rest_frames, 0, 10000);
  c.blend_frames = f.integer("blend_frames", c.blend_frames, 1, 10000);
  {
    Fields s = f.object("sequences");
    c.train = s.integer("train", 0, 0, 1000000);
    c.validation = s.integer("validation", 0, 0, 1000000);
    c.test = s.integer("test", 0, 0, 1000000);
    c.held_out = s.integer("held_out", 0, 0, 1000000);
    s.done();
    if (c.train + c.validation + c.test + c.held_out == 0) s.bad("asks for no sequence");
  }
  c.garments = read_list<GarmentSpec>(f, "garments", [&](Fields& g) {
    GarmentSpec spec;
    spec.mhclo = resolve(assets, g.text("mhclo", "", true));
    require_file(g, spec.mhclo, "mhclo");
    spec.name = checked_name(g, "name", fs::path(spec.mhclo).stem().string());
    spec.held_out = g.flag("held_out", false);
    spec.pin_distance = g.number("pin_distance", spec.pin_distance, 0, 0.2);
    spec.pin_band = g.number("pin_band", spec.pin_band, 0.001, 2);
    if (g.has("stretch")) {
      Fields s = g.object("stretch");
      spec.stretch_below = s.number("below", 0, 0, 1);
      spec.stretch_factor = s.number("factor", 1, 1, 8);
      s.done();
      if (spec.stretch_below == 0 || spec.stretch_factor == 1) s.bad("needs 'below' > 0 and 'factor' > 1");
    }
    return spec;
  });
  c.shapes = read_list<ShapeSpec>(f, "shapes", [&](Fields& s) {
    ShapeSpec spec;
    spec.name = checked_name(s, "name", "");
    if (s.has("values")) {
      const Json& v = s.at("values");
      if (!v.is_object()) s.bad("must be an object of shape entries", "values");
      for (const auto& [key, value] : v.items()) {
        if (!value.is_number()) s.bad("must be a number", "values." + key);
        spec.values.emplace_back(key, value.get<double>());
      }
    }
    return spec;
  });
  c.motions = read_list<MotionSpec>(f, "motions", [&](Fields& m) {
    MotionSpec spec;
    spec.source = resolve(assets, m.text("source", "", true));
    require_file(m, spec.source, "source");
    spec.speed = m.number("speed", 1.0, 0.25, 4.0);
    spec.turn = m.number("turn", 0.0, -1440.0, 1440.0);
    // A time-warped or turned clip is another clip: its default name says how.
    spec.name = checked_name(m, "name", clip_name(spec.source, spec.speed, spec.turn));
    if (m.has("map")) {
      spec.map = resolve(base, m.text("map"));
      require_file(m, spec.map, "map");
    }
    spec.skip_frames = m.integer("skip_frames", 0, 0, 1000000);
    spec.take_frames = m.integer("take_frames", 0, 0, 1000000);
    spec.hold_frames = m.integer("hold_frames", 0, 0, 1000000);
    spec.split = m.text("split", "train");
    if (spec.split != "train" && spec.split != "validation" && spec.split != "test")
      m.bad("must be \"train\", \"validation\" or \"test\"", "split");
    return spec;
  });
  if (f.has("cloth")) read_cloth(f.object("cloth"), &c.cloth);
  if (f.has("collision")) read_collision(f.object("collision"), &c.collision);
  if (f.has("check")) read_check(f.object("check"), &c.check);
  if (f.has("twins")) {
    Fields t = f.object("twins");
    c.twins.split = t.text("split", "", true);
    if (c.twins.split != "train" && c.twins.split != "validation" && c.twins.split != "test")
      t.bad("must be \"train\", \"validation\" or \"test\"", "split");
    c.twins.mass_scale = t.number("mass_scale", c.twins.mass_scale, 0.5, 2);
    c.twins.extra_rest_frames = t.integer("extra_rest_frames", c.twins.extra_rest_frames, 0, 10000);
    t.done();
    if (c.twins.mass_scale == 1.0 && c.twins.extra_rest_frames == 0)
      t.bad("perturbs nothing: a twin would repeat its sequence exactly");
  }
  f.done();

  // Every split that asks for sequences needs garments and clips to draw from.
  const auto count_if = [](const auto& list, auto&& predicate) {
    return std::count_if(list.begin(), list.end(), predicate);
  };
  const auto seen = count_if(c.garments, [](const GarmentSpec& g) { return !g.held_out; });
  for (const char* split : {"train", "validation", "test"}) {
    const int64_t wanted = split == std::string("train")        ? c.train
                           : split == std::string("validation") ? c.validation
                                                                : c.test;
    if (wanted == 0) continue;
    if (seen == 0)
      f.bad("asks for " + std::string(split) + " sequences, but every garment is held out", "sequences");
    if (count_if(c.motions, [&](const MotionSpec& m) { return m.split == split; }) == 0)
      f.bad("asks for " + std::string(split) + " sequences, but no motion has that split", "sequences");
  }
  if (c.held_out > 0 && seen == static_cast<int64_t>(c.garments.size()))
    f.bad("asks for held_out sequences, but no garment is held out", "sequences");
  return c;
}

Config read_config(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(PLEAT_ERROR_IO, "datagen config '" + path + "': cannot open the file");
  std::stringstream text;
  text << in.rdbuf();
  return parse_config(text.str(), path);
}

Config twin_config(const Config& config) {
  Config twin = config;
  twin.cloth.mass *= config.twins.mass_scale;
  twin.rest_frames += config.twins.extra_rest_frames;
  return twin;
}

std::string output_dir(const Config& config) {
  return config.output.empty() ? default_dataset_dir(config.name) : config.output;
}

}  // namespace pleat::datagen
