// JSON pieces the bench groups' record writers share (terrain_records.cpp, blocker_records.cpp,
// probe_records.cpp).
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
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

// Short names for the two above, as the record writers use them.
inline std::string jnum(std::optional<double> v, int precision = 6) {
  return number(v, precision);
}
inline std::string jstr(const std::string& s) {
  return string(s);
}

// A number as printf's %g writes it (in keys and labels).
inline std::string compact(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// The 1-minute load average, if the system gives it (other processes make the 2-thread timings
// slower; every record file notes it).
inline std::optional<double> load_average() {
  double l[1];
  if (getloadavg(l, 1) != 1) return std::nullopt;
  return l[0];
}

}  // namespace penumbra::bench_json
