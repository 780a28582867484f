// JSON pieces the bench groups' record writers share (terrain_records.cpp, blocker_records.cpp).
#pragma once

#include <cmath>
#include <optional>
#include <sstream>
#include <string>

namespace penumbra::bench_json {

// A number, or null when absent or not finite.
inline std::string number(std::optional<double> v, int precision = 6) {
  if (!v || !std::isfinite(*v)) return "null";
  std::ostringstream o;
  o.precision(precision);
  o << *v;
  return o.str();
}

// A quoted string with '"' and '\' escaped.
inline std::string string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace penumbra::bench_json
