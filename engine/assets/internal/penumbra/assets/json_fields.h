// JsonFields: reads the fields of a JSON scene file (nlohmann-json) with every error naming the
// file, the field's path and the reason ("scenes/x.json: objects[2].albedo: missing"). Shared by
// the probe bake's scene files (systems/probe_bake bake_scene.cpp) and the tune scenes that
// extend them (game/tune tune_scene.cpp). Build-tree only: not installed (nlohmann-json stays
// out of the public headers); targets add engine/assets/internal to their private includes.
// Threading: const, any thread.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

namespace penumbra::assets {

class JsonFields {
 public:
  using Json = nlohmann::json;
  explicit JsonFields(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& why) const {
    throw std::runtime_error(file_ + ": " + path + ": " + why);
  }
  // j is an object whose keys are all in `allowed`.
  void only(const Json& j, const std::string& path, const std::set<std::string>& allowed) const {
    if (!j.is_object()) fail(path, std::string("expected an object, got ") + j.type_name());
    for (const auto& [k, v] : j.items())
      if (!allowed.count(k)) fail(path + "." + k, "unknown field");
  }
  const Json& field(const Json& j, const std::string& path, const char* key) const {
    const auto it = j.find(key);
    if (it == j.end()) fail(path + "." + key, "missing");
    return *it;
  }
  float number(const Json& v, const std::string& path) const {
    if (!v.is_number()) fail(path, std::string("expected a number, got ") + v.type_name());
    const double d = v.get<double>();
    if (!std::isfinite(d) || !std::isfinite(static_cast<float>(d))) fail(path, "not finite");
    return static_cast<float>(d);
  }
  float number(const Json& j, const std::string& path, const char* key) const {
    return number(field(j, path, key), path + "." + key);
  }
  float number_or(const Json& j, const std::string& path, const char* key, float def) const {
    return j.contains(key) ? number(j, path, key) : def;
  }
  float positive(const Json& j, const std::string& path, const char* key) const {
    const float v = number(j, path, key);
    if (!(v > 0)) fail(path + "." + key, "must be > 0, got " + std::to_string(v));
    return v;
  }
  int integer(const Json& j, const std::string& path, const char* key, int lo, int hi) const {
    const Json& v = field(j, path, key);
    if (!v.is_number_integer()) fail(path + "." + key, "expected an integer");
    const auto i = v.get<long long>();
    if (i < lo || i > hi)
      fail(path + "." + key, "out of range [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                 "]: " + std::to_string(i));
    return static_cast<int>(i);
  }
  template <std::size_t K>
  std::array<float, K> vec(const Json& j, const std::string& path, const char* key) const {
    const Json& v = field(j, path, key);
    const std::string p = path + "." + key;
    if (!v.is_array() || v.size() != K)
      fail(p, "expected an array of " + std::to_string(K) + " numbers");
    std::array<float, K> out{};
    for (std::size_t i = 0; i < K; ++i) out[i] = number(v[i], p + "[" + std::to_string(i) + "]");
    return out;
  }
  glm::vec3 vec3(const Json& j, const std::string& path, const char* key) const {
    const auto a = vec<3>(j, path, key);
    return {a[0], a[1], a[2]};
  }
  std::string string(const Json& j, const std::string& path, const char* key) const {
    const Json& v = field(j, path, key);
    if (!v.is_string())
      fail(path + "." + key, std::string("expected a string, got ") + v.type_name());
    return v.get<std::string>();
  }

 private:
  std::string file_;
};

}  // namespace penumbra::assets
