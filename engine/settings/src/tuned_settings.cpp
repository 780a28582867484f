#include "penumbra/settings/tuned_settings.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <set>
#include <span>
#include <stdexcept>
#include <system_error>

#include <nlohmann/json.hpp>

#include "penumbra/assets/atomic_write.h"
#include "penumbra/assets/checksum.h"
#include "penumbra/assets/load_error.h"

namespace penumbra::settings {

namespace {

using Json = nlohmann::ordered_json;

std::uint64_t checksum(std::string_view payload) {
  return assets::fnv1a64({reinterpret_cast<const unsigned char*>(payload.data()), payload.size()});
}

// --- Reading: every field checked, the path in the message ------------------------------------

struct Reader {
  const std::string& file;
  [[noreturn]] void fail(const std::string& path, const std::string& reason) const {
    throw assets::LoadError(file, path.empty() ? reason : path + ": " + reason);
  }
  static const char* type_name(const Json& j) { return j.type_name(); }

  const Json& object(const Json& parent, const std::string& key, const std::string& path,
                     std::initializer_list<const char*> fields) const {
    const Json& j = field(parent, key, path);
    const std::string p = join(path, key);
    if (!j.is_object()) fail(p, std::string("expected an object, got ") + type_name(j));
    check_fields(j, p, fields);
    return j;
  }
  void check_fields(const Json& j, const std::string& path,
                    std::initializer_list<const char*> fields) const {
    const std::set<std::string> known(fields.begin(), fields.end());
    for (const auto& [k, v] : j.items())
      if (!known.count(k)) fail(join(path, k), "unknown field");
  }
  const Json& field(const Json& parent, const std::string& key, const std::string& path) const {
    const auto it = parent.find(key);
    if (it == parent.end()) fail(join(path, key), "missing");
    return *it;
  }
  double number(const Json& parent, const std::string& key, const std::string& path, double lo,
                double hi, bool open_lo = false, bool open_hi = false) const {
    const Json& j = field(parent, key, path);
    const std::string p = join(path, key);
    if (!j.is_number()) fail(p, std::string("expected a number, got ") + type_name(j));
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(p, "not finite");
    if ((open_lo ? !(v > lo) : !(v >= lo)) || (open_hi ? !(v < hi) : !(v <= hi)))
      fail(p, "out of range: " + j.dump() + " not in " + (open_lo ? "(" : "[") + fmt(lo) + ", " +
                  fmt(hi) + (open_hi ? ")" : "]"));
    return v;
  }
  int integer(const Json& parent, const std::string& key, const std::string& path, int lo,
              int hi) const {
    const Json& j = field(parent, key, path);
    const std::string p = join(path, key);
    if (!j.is_number_integer())
      fail(p, std::string("expected an integer, got ") + (j.is_number() ? j.dump() : type_name(j)));
    const bool huge =
        j.is_number_unsigned() && j.get<std::uint64_t>() > static_cast<std::uint64_t>(hi);
    if (huge || j.get<std::int64_t>() < lo || j.get<std::int64_t>() > hi)
      fail(p, "out of range: " + j.dump() + " not in [" + std::to_string(lo) + ", " +
                  std::to_string(hi) + "]");
    return static_cast<int>(j.get<std::int64_t>());
  }
  bool boolean(const Json& parent, const std::string& key, const std::string& path) const {
    const Json& j = field(parent, key, path);
    if (!j.is_boolean()) fail(join(path, key), std::string("expected a bool, got ") + type_name(j));
    return j.get<bool>();
  }
  std::string text(const Json& parent, const std::string& key, const std::string& path,
                   std::initializer_list<const char*> allowed = {}) const {
    const Json& j = field(parent, key, path);
    const std::string p = join(path, key);
    if (!j.is_string()) fail(p, std::string("expected a string, got ") + type_name(j));
    std::string v = j.get<std::string>();
    if (allowed.size() == 0) return v;
    std::string list;
    for (const char* a : allowed) {
      if (v == a) return v;
      list += std::string(list.empty() ? "" : ", ") + a;
    }
    fail(p, "unknown value \"" + v + "\" (expected one of " + list + ")");
  }
  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }
  static std::string fmt(double v) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
  }

  TuneResult result(const Json& parent, const std::string& path) const {
    const Json& j = object(parent, "result", path,
                           {"tuned", "error", "met", "cost", "ms", "evaluations", "grid"});
    const std::string p = join(path, "result");
    constexpr double kInf = std::numeric_limits<double>::infinity();
    TuneResult r;
    r.tuned = boolean(j, "tuned", p);
    r.error = number(j, "error", p, 0, kInf, false, true);
    r.met = boolean(j, "met", p);
    r.cost = number(j, "cost", p, 0, kInf, false, true);
    r.ms = number(j, "ms", p, 0, kInf, false, true);
    r.evaluations = integer(j, "evaluations", p, 0, std::numeric_limits<int>::max());
    r.grid = integer(j, "grid", p, 0, std::numeric_limits<int>::max());
    return r;
  }
};

// --- Writing -----------------------------------------------------------------------------------

Json result_json(const TuneResult& r) {
  return Json{{"tuned", r.tuned}, {"error", r.error}, {"met", r.met},
              {"cost", r.cost},   {"ms", r.ms},       {"evaluations", r.evaluations},
              {"grid", r.grid}};
}

std::string payload_of(const TunedSettings& s) {
  Json j;
  j["scene"] = s.scene;
  j["budget"] = s.budget;
  j["terrain"] = Json{{"horizon", s.terrain.horizon},
                      {"level_step", s.terrain.level_step},
                      {"azimuths", s.terrain.azimuths},
                      {"bands", s.terrain.bands},
                      {"result", result_json(s.terrain.result)}};
  j["blockers"] = Json{{"spheres_per_object", s.blockers.spheres_per_object},
                       {"epsilon", s.blockers.epsilon},
                       {"bands", s.blockers.bands},
                       {"result", result_json(s.blockers.result)}};
  j["spherical_lights"] = Json{{"directions_frequency", s.spherical_lights.directions_frequency},
                               {"blocking", s.spherical_lights.blocking},
                               {"horizon", s.spherical_lights.horizon},
                               {"gather", s.spherical_lights.gather},
                               {"result", result_json(s.spherical_lights.result)}};
  j["probes"] = Json{{"spacing", s.probes.spacing},
                     {"probes_per_side", s.probes.probes_per_side},
                     {"placement", s.probes.placement},
                     {"result", result_json(s.probes.result)}};
  return j.dump(2) + "\n";
}

TunedSettings parse_payload(const Json& j, const std::string& name) {
  const Reader r{name};
  if (!j.is_object()) r.fail("", std::string("payload: expected an object, got ") + j.type_name());
  r.check_fields(j, "", {"scene", "budget", "terrain", "blockers", "spherical_lights", "probes"});
  constexpr double kInf = std::numeric_limits<double>::infinity();
  TunedSettings s;
  s.scene = r.text(j, "scene", "");
  s.budget = r.number(j, "budget", "", 0, kInf, true, true);
  {
    const Json& t =
        r.object(j, "terrain", "", {"horizon", "level_step", "azimuths", "bands", "result"});
    s.terrain.horizon = r.text(t, "horizon", "terrain", {"sweep", "march"});
    s.terrain.level_step = r.integer(t, "level_step", "terrain", 1, 16);
    s.terrain.azimuths = r.integer(t, "azimuths", "terrain", 3, 256);
    s.terrain.bands = r.integer(t, "bands", "terrain", 3, 6);
    s.terrain.result = r.result(t, "terrain");
  }
  {
    const Json& b =
        r.object(j, "blockers", "", {"spheres_per_object", "epsilon", "bands", "result"});
    s.blockers.spheres_per_object = r.integer(b, "spheres_per_object", "blockers", 1, 1024);
    s.blockers.epsilon = static_cast<float>(r.number(b, "epsilon", "blockers", 0, 1, true, true));
    s.blockers.bands = r.integer(b, "bands", "blockers", 3, 6);
    s.blockers.result = r.result(b, "blockers");
  }
  {
    const Json& l = r.object(j, "spherical_lights", "",
                             {"directions_frequency", "blocking", "horizon", "gather", "result"});
    s.spherical_lights.directions_frequency =
        r.integer(l, "directions_frequency", "spherical_lights", 1, 8);
    s.spherical_lights.blocking =
        r.text(l, "blocking", "spherical_lights", {"per_sphere", "per_object"});
    s.spherical_lights.horizon = r.text(l, "horizon", "spherical_lights", {"shrink", "clip"});
    // Optional: files from before the knob lack it (per receiver, what they were tuned with).
    if (l.contains("gather"))
      s.spherical_lights.gather = r.text(l, "gather", "spherical_lights",
                                         {"receivers", "clusters_leaves", "clusters_parents"});
    s.spherical_lights.result = r.result(l, "spherical_lights");
  }
  {
    const Json& p =
        r.object(j, "probes", "", {"spacing", "probes_per_side", "placement", "result"});
    s.probes.spacing = static_cast<float>(r.number(p, "spacing", "probes", 0, 1e6, true, false));
    s.probes.probes_per_side = r.integer(p, "probes_per_side", "probes", 2, 1024);
    s.probes.placement = r.text(p, "placement", "probes", {"grid", "spawn_merge", "gradient"});
    s.probes.result = r.result(p, "probes");
  }
  return s;
}

// Parses an unsigned decimal token of at most `digits` digits; false when it is not one.
bool parse_decimal(std::string_view token, std::size_t digits, std::uint64_t& out) {
  if (token.empty() || token.size() > digits) return false;
  out = 0;
  for (char c : token) {
    if (c < '0' || c > '9') return false;
    out = out * 10 + static_cast<std::uint64_t>(c - '0');
  }
  return true;
}

}  // namespace

std::string encode_settings(const TunedSettings& settings) {
  const std::string payload = payload_of(settings);
  // The writer checks what the reader checks: a settings value the reader would reject is a
  // caller's bug, reported before anything is written.
  try {
    parse_payload(Json::parse(payload), "(settings being written)");
  } catch (const assets::LoadError& e) {
    throw std::invalid_argument("encode_settings: " + e.reason());
  }
  char header[96];
  std::snprintf(header, sizeof header, "%s %u %zu %016llx\n", kSettingsMagic.data(),
                kSettingsVersion, payload.size(),
                static_cast<unsigned long long>(checksum(payload)));
  return header + payload;
}

TunedSettings parse_settings(std::string_view bytes, const std::string& name) {
  if (bytes.empty()) throw assets::LoadError(name, "empty file");
  const std::size_t eol = bytes.find('\n');
  if (eol == std::string_view::npos || eol > 128)
    throw assets::LoadError(name, "no header line (not a penumbra settings file)");
  const std::string_view header = bytes.substr(0, eol);
  std::string_view fields[4];
  std::size_t n = 0, pos = 0;
  while (pos <= header.size() && n < 5) {
    const std::size_t sp = header.find(' ', pos);
    const std::size_t end = sp == std::string_view::npos ? header.size() : sp;
    if (n == 4) throw assets::LoadError(name, "header: more than 4 fields");
    fields[n++] = header.substr(pos, end - pos);
    if (sp == std::string_view::npos) break;
    pos = sp + 1;
  }
  if (n == 0 || fields[0] != kSettingsMagic)
    throw assets::LoadError(name, "header: not a penumbra settings file (expected \"" +
                                      std::string(kSettingsMagic) + "\")");
  if (n != 4)
    throw assets::LoadError(
        name,
        "header: expected 4 fields (magic version length checksum), got " + std::to_string(n));
  std::uint64_t version = 0, length = 0;
  if (!parse_decimal(fields[1], 9, version))
    throw assets::LoadError(name, "header: bad version \"" + std::string(fields[1]) + "\"");
  if (version != kSettingsVersion)
    throw assets::LoadError(name, "unsupported version " + std::to_string(version) +
                                      " (this build reads version " +
                                      std::to_string(kSettingsVersion) + ")");
  if (!parse_decimal(fields[2], 9, length) || length > kMaxSettingsPayload)
    throw assets::LoadError(name, "header: bad payload length \"" + std::string(fields[2]) + "\"");
  if (fields[3].size() != 16 ||
      fields[3].find_first_not_of("0123456789abcdef") != std::string_view::npos)
    throw assets::LoadError(name, "header: bad checksum field \"" + std::string(fields[3]) +
                                      "\" (expected 16 lowercase hex digits)");
  const std::string_view payload = bytes.substr(eol + 1);
  if (payload.size() < length)
    throw assets::LoadError(name, "truncated: payload has " + std::to_string(payload.size()) +
                                      " of " + std::to_string(length) + " bytes");
  if (payload.size() > length)
    throw assets::LoadError(
        name, std::to_string(payload.size() - length) + " trailing bytes after the payload");
  const std::uint64_t expected = std::stoull(std::string(fields[3]), nullptr, 16);
  if (checksum(payload) != expected)
    throw assets::LoadError(name, "checksum mismatch (the file is corrupt)");
  Json j;
  try {
    j = Json::parse(payload);
  } catch (const Json::exception& e) {
    throw assets::LoadError(name, std::string("payload is not JSON: ") + e.what());
  }
  return parse_payload(j, name);
}

TunedSettings load_settings(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    std::error_code ec;
    throw assets::LoadError(
        file.string(), std::filesystem::exists(file, ec) ? "cannot be opened" : "no such file");
  }
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw assets::LoadError(file.string(), "read error");
  return parse_settings(bytes, file.string());
}

void save_settings(const std::filesystem::path& file, const TunedSettings& settings) {
  assets::write_file_atomic(file, encode_settings(settings));
}

}  // namespace penumbra::settings
