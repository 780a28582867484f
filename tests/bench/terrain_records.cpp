// The terrain group's records (JSON) and speed-versus-accuracy chart (SVG): terrain_records.h.
#include "terrain_records.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace penumbra::terrain_bench {
namespace {

std::string jnum(std::optional<double> v, int precision = 6) {
  if (!v || !std::isfinite(*v)) return "null";
  std::ostringstream o;
  o.precision(precision);
  o << *v;
  return o.str();
}

std::string jstr(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// 1-minute load average (other processes make the 2-thread timings slower), if available.
std::optional<double> load_average() {
  double l[1];
  if (getloadavg(l, 1) != 1) return std::nullopt;
  return l[0];
}

// Series of the chart: one colour per method and varied parameter.
std::string series_of(const CaseInfo& c) {
  if (c.env.method == "march") {
    if (c.env.n_phi != 32) return "march ls 4 lo 2, n_phi";
    return "march lo " + std::to_string(static_cast<int>(c.env.lo)) + ", ls (n_phi 32)";
  }
  if (c.env.method == "sweep") return c.env.bands != 4 ? "sweep, bands 3 and 5" : "sweep, n_phi";
  return "brute force (n_phi 32)";
}
// A point's label: its varied parameter ("ls3", "n16", "N5 n8", "bf").
std::string label_of(const CaseInfo& c) {
  const auto tagged = [](const char* tag, int value) {
    std::string s(tag);  // not tag + std::to_string(): GCC 12's -Wrestrict false positive
    s += std::to_string(value);
    return s;
  };
  if (c.env.method == "march" && c.env.n_phi == 32) return tagged("ls", c.env.ls);
  if (c.env.bands != 4)
    return tagged("N", c.env.bands) + (c.env.n_phi != 32 ? tagged(" n", c.env.n_phi) : "");
  if (c.env.method == "brute_force") return "bf";
  return tagged("n", c.env.n_phi);
}
std::string svg_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

}  // namespace

bool write_atomically(const std::string& path, const std::string& text) {
  const std::filesystem::path p(path);
  std::error_code ec;
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path(), ec);
  const std::filesystem::path tmp = p.string() + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary);
    if (!f) return false;
    f << text;
    if (!f.flush()) return false;
  }
  std::filesystem::rename(tmp, p, ec);
  return !ec;
}

bool on_chart(const Record& r) {
  const CaseInfo& c = *r.info;
  return c.is_env && c.size == kSize && r.ms && r.error.rel_rms &&
         (c.kind == "sweep" || c.method == "brute_force");
}

std::string records_json(const std::vector<Record>& records, const std::string& best) {
  std::ostringstream o;
  o << "{\n  \"group\": \"terrain\",\n  \"scene\": " << jstr(tbr::kSceneName)
    << ",\n  \"environment\": " << jstr(tbr::environment_name())
    << ",\n  \"reference\": " << jstr(tbr::reference_description())
    << ",\n  \"threads\": " << std::thread::hardware_concurrency()
    << ",\n  \"load_avg_at_end\": " << jnum(load_average())
    << ",\n  \"best_tradeoff_rule\": \"most accurate chart point within 10 ms; if none, smallest "
       "ms x rel_rms\""
    << ",\n  \"best_tradeoff\": " << jstr(best) << ",\n  \"records\": [";
  for (std::size_t i = 0; i < records.size(); ++i) {
    const Record& r = records[i];
    const CaseInfo& c = *r.info;
    o << (i ? ",\n" : "\n") << "    {\"case\": " << jstr(c.key) << ", \"kind\": " << jstr(c.kind)
      << ", \"scene\": " << jstr(tbr::kSceneName) << ", \"method\": " << jstr(c.method)
      << ", \"params\": " << c.params_json << ", \"size\": " << c.size << ", \"ms\": " << jnum(r.ms)
      << ", \"floor_ms\": " << jnum(r.floor_ms)
      << ", \"ratio_to_floor\": " << jnum(pb::quotient(r.ms, r.floor_ms))
      << ", \"goal_ms\": " << jnum(c.goal_ms) << ", \"goal_met\": ";
    if (c.goal_ms && r.ms)
      o << (*r.ms <= *c.goal_ms ? "true" : "false");
    else
      o << "null";
    o << ", \"rel_rms_error\": " << jnum(r.error.rel_rms)
      << ", \"max_rel_error\": " << jnum(r.error.max_rel)
      << ", \"reference_rel_se\": " << jnum(r.error.ref_rel_se) << "}";
  }
  o << "\n  ]\n}\n";
  return o.str();
}

std::string chart_svg(const std::vector<Record>& records, const std::string& best_key) {
  struct Point {
    double ms, err;
    std::string series, label, key;
  };
  std::vector<Point> pts;
  for (const Record& r : records) {
    if (!on_chart(r)) continue;
    pts.push_back(
        {*r.ms, *r.error.rel_rms * 100, series_of(*r.info), label_of(*r.info), r.info->key});
  }
  const double W = 920, H = 600, left = 80, right = 250, top = 50, bottom = 70;
  const double pw = W - left - right, ph = H - top - bottom;
  std::ostringstream o;
  o.precision(5);
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
    << "\" viewBox=\"0 0 " << W << " " << H << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
    << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << left
    << "\" y=\"24\" font-size=\"15\" font-weight=\"bold\">Terrain shadows: "
       "full environment update, "
    << kSize << "x" << kSize << " " << tbr::kSceneName << ", 2 threads</text>\n"
    << "<text x=\"" << left
    << "\" y=\"40\" fill=\"#555\">irradiance error vs Monte Carlo reference ("
    << svg_escape(tbr::environment_name())
    << "); n = n_phi, ls = level step, N = SH bands</text>\n";
  if (pts.empty()) {
    o << "<text x=\"" << left + 20 << "\" y=\"" << top + ph / 2
      << "\">no points with a reference error in this run</text>\n</svg>\n";
    return o.str();
  }
  double tmin = 1e300, tmax = 0, emax = 0;
  for (const Point& p : pts) {
    tmin = std::min(tmin, p.ms);
    tmax = std::max(tmax, p.ms);
    emax = std::max(emax, p.err);
  }
  const double lx0 = std::floor(std::log10(tmin)), lx1 = std::ceil(std::log10(tmax));
  const double x_span = std::max(lx1 - lx0, 1.0);
  // Error axis: linear from 0 to a round step above the largest error.
  const double raw = emax / 5;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw / mag <= 1   ? mag
                      : raw / mag <= 2 ? 2 * mag
                      : raw / mag <= 5 ? 5 * mag
                                       : 10 * mag;
  const double ymax = step * std::ceil(emax * 1.08 / step);
  auto X = [&](double ms) { return left + (std::log10(ms) - lx0) / x_span * pw; };
  auto Y = [&](double e) { return top + ph - e / ymax * ph; };

  o << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
    << "\" fill=\"none\" stroke=\"#333\"/>\n";
  for (int d = static_cast<int>(lx0); d <= static_cast<int>(lx0 + x_span); ++d) {
    for (int m = 1; m <= 9; ++m) {
      const double v = m * std::pow(10.0, d);
      if (std::log10(v) > lx0 + x_span + 1e-9) break;
      const double x = X(v);
      o << "<line x1=\"" << x << "\" y1=\"" << top << "\" x2=\"" << x << "\" y2=\"" << top + ph
        << "\" stroke=\"" << (m == 1 ? "#bbb" : "#eee") << "\"/>\n";
      if (m == 1 || m == 2 || m == 5) {
        std::ostringstream label;
        label << v;
        o << "<text x=\"" << x << "\" y=\"" << top + ph + 16 << "\" text-anchor=\"middle\">"
          << label.str() << "</text>\n";
      }
    }
  }
  for (double e = 0; e <= ymax + 1e-12; e += step) {
    const double y = Y(e);
    o << "<line x1=\"" << left << "\" y1=\"" << y << "\" x2=\"" << left + pw << "\" y2=\"" << y
      << "\" stroke=\"#eee\"/>\n<text x=\"" << left - 6 << "\" y=\"" << y + 4
      << "\" text-anchor=\"end\">" << e << "</text>\n";
  }
  // The 10 ms goal.
  if (10 >= std::pow(10.0, lx0) && 10 <= std::pow(10.0, lx0 + x_span)) {
    o << "<line x1=\"" << X(10) << "\" y1=\"" << top << "\" x2=\"" << X(10) << "\" y2=\""
      << top + ph << "\" stroke=\"#c33\" stroke-dasharray=\"6 4\"/>\n<text x=\"" << X(10) + 4
      << "\" y=\"" << top + 14 << "\" fill=\"#c33\">goal 10 ms</text>\n";
  }
  o << "<text x=\"" << left + pw / 2 << "\" y=\"" << H - 24
    << "\" text-anchor=\"middle\">time of the full environment update, ms (log scale)</text>\n"
    << "<text x=\"22\" y=\"" << top + ph / 2
    << "\" text-anchor=\"middle\" transform=\"rotate(-90 22 " << top + ph / 2
    << ")\">relative RMS irradiance error, %</text>\n";

  // Pareto front (no other point both faster and more accurate).
  std::vector<Point> sorted = pts;
  std::sort(sorted.begin(), sorted.end(),
            [](const Point& a, const Point& b) { return a.ms < b.ms; });
  std::string path;
  double best_err = 1e300;
  for (const Point& p : sorted)
    if (p.err < best_err) {
      best_err = p.err;
      path +=
          (path.empty() ? "M" : " L") + std::to_string(X(p.ms)) + " " + std::to_string(Y(p.err));
    }
  o << "<path d=\"" << path << "\" fill=\"none\" stroke=\"#999\" stroke-dasharray=\"3 3\"/>\n";

  const char* colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728",
                           "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"};
  std::vector<std::string> series;
  for (const Point& p : pts)
    if (std::find(series.begin(), series.end(), p.series) == series.end())
      series.push_back(p.series);
  // Circles first, then each label at the first of six spots around its point that overlaps
  // no circle and no label placed so far.
  struct Box {
    double x0, y0, x1, y1;
    bool overlaps(const Box& b) const { return x0 < b.x1 && b.x0 < x1 && y0 < b.y1 && b.y0 < y1; }
  };
  std::vector<Box> taken;
  auto colour_of = [&](const Point& p) {
    return colours[(std::find(series.begin(), series.end(), p.series) - series.begin()) % 8];
  };
  for (const Point& p : pts) {
    const double x = X(p.ms), y = Y(p.err);
    o << "<circle cx=\"" << x << "\" cy=\"" << y << "\" r=\"5\" fill=\"" << colour_of(p) << "\"";
    if (p.key == best_key) o << " stroke=\"black\" stroke-width=\"2\"";
    o << "><title>" << svg_escape(p.key) << ": " << p.ms << " ms, " << p.err
      << " %</title></circle>\n";
    taken.push_back({x - 5, y - 5, x + 5, y + 5});
  }
  for (const Point& p : pts) {
    const double x = X(p.ms), y = Y(p.err);
    const double w = 6.0 * p.label.size(), h = 10;
    const double spots[6][2] = {{7, -4}, {7, 13}, {-7 - w, -4}, {-7 - w, 13}, {8, 4}, {-8 - w, 4}};
    Box chosen{};
    for (int k = 0; k < 6; ++k) {
      const Box b{x + spots[k][0], y + spots[k][1] - h, x + spots[k][0] + w, y + spots[k][1]};
      if (k == 0) chosen = b;
      bool free = true;
      for (const Box& t : taken)
        free = free && !(t.overlaps(b) && !(t.x0 == x - 5 && t.y0 == y - 5));
      if (free) {
        chosen = b;
        break;
      }
    }
    taken.push_back(chosen);
    o << "<text x=\"" << chosen.x0 << "\" y=\"" << chosen.y1 << "\" font-size=\"10\" fill=\""
      << colour_of(p) << "\">" << svg_escape(p.label) << "</text>\n";
  }
  const double lx = left + pw + 16;
  double ly = top + 10;
  o << "<text x=\"" << lx << "\" y=\"" << ly << "\" font-weight=\"bold\">method</text>\n";
  for (std::size_t s = 0; s < series.size(); ++s) {
    ly += 20;
    o << "<circle cx=\"" << lx + 6 << "\" cy=\"" << ly - 4 << "\" r=\"5\" fill=\"" << colours[s % 8]
      << "\"/><text x=\"" << lx + 16 << "\" y=\"" << ly << "\">" << svg_escape(series[s])
      << "</text>\n";
  }
  ly += 28;
  o << "<text x=\"" << lx << "\" y=\"" << ly
    << "\" fill=\"#555\">dashed grey: Pareto front</text>\n"
    << "<text x=\"" << lx << "\" y=\"" << ly + 16
    << "\" fill=\"#555\">ringed: best trade-off</text>\n"
    << "<text x=\"" << lx << "\" y=\"" << ly + 32
    << "\" fill=\"#555\">n_phi 32 unless labelled nK</text>\n"
    << "<text x=\"" << lx << "\" y=\"" << ly + 48
    << "\" fill=\"#555\">march: pyramid build included</text>\n";
  o << "</svg>\n";
  return o.str();
}

}  // namespace penumbra::terrain_bench
