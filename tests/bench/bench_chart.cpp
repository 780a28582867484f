// Speed-versus-accuracy chart (SVG) and atomic writes of a group's outputs: bench_chart.h.
#include "bench_chart.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace penumbra::bench {
namespace {

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

const char* const kPalette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728",
                                "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"};
const char* const kDashes[] = {"", "6 4", "2 3"};

// A round step (1, 2 or 5 x 10^k) giving about five intervals up to `max`.
double round_step(double max) {
  const double raw = max > 0 ? max / 5 : 0.2;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  return raw / mag <= 1 ? mag : raw / mag <= 2 ? 2 * mag : raw / mag <= 5 ? 5 * mag : 10 * mag;
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

namespace {

// Both charts' frame: 920 x 600, the title and subtitle above the plot at x = left.
constexpr double kWidth = 920, kHeight = 600;
void svg_open(std::ostringstream& o, const std::string& title, const std::string& subtitle,
              double left) {
  o.precision(5);
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << kHeight
    << "\" viewBox=\"0 0 " << kWidth << " " << kHeight
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
    << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << left << "\" y=\"24\" font-size=\"15\" font-weight=\"bold\">"
    << svg_escape(title) << "</text>\n"
    << "<text x=\"" << left << "\" y=\"40\" fill=\"#555\">" << svg_escape(subtitle) << "</text>\n";
}

}  // namespace

std::string chart_svg(const ChartSpec& spec, const std::vector<ChartPoint>& pts) {
  const double W = kWidth, H = kHeight, left = 80, right = 250, top = 50, bottom = 70;
  const double pw = W - left - right, ph = H - top - bottom;
  std::ostringstream o;
  svg_open(o, spec.title, spec.subtitle, left);
  if (pts.empty()) {
    o << "<text x=\"" << left + 20 << "\" y=\"" << top + ph / 2 << "\">"
      << svg_escape(spec.empty_text) << "</text>\n</svg>\n";
    return o.str();
  }
  double tmin = 1e300, tmax = 0, emax = 0;
  for (const ChartPoint& p : pts) {
    tmin = std::min(tmin, p.ms);
    tmax = std::max(tmax, p.ms);
    emax = std::max(emax, p.error_percent);
  }
  const bool clipped = spec.error_limit && emax > *spec.error_limit;
  if (clipped) emax = *spec.error_limit;
  const double lx0 = std::floor(std::log10(tmin)), lx1 = std::ceil(std::log10(tmax));
  const double x_span = std::max(lx1 - lx0, 1.0);
  // Error axis: linear from 0 to a round step above the largest error.
  const double raw = emax > 0 ? emax / 5 : 0.2;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw / mag <= 1   ? mag
                      : raw / mag <= 2 ? 2 * mag
                      : raw / mag <= 5 ? 5 * mag
                                       : 10 * mag;
  const double ymax = std::max(step * std::ceil(emax * (clipped ? 1.0 : 1.08) / step), step);
  auto X = [&](double ms) { return left + (std::log10(ms) - lx0) / x_span * pw; };
  auto Y = [&](double e) { return top + ph - std::min(e, ymax) / ymax * ph; };
  auto above = [&](const ChartPoint& p) { return clipped && p.error_percent > ymax; };

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
  if (spec.goal_ms && *spec.goal_ms >= std::pow(10.0, lx0) &&
      *spec.goal_ms <= std::pow(10.0, lx0 + x_span)) {
    const double g = *spec.goal_ms;
    o << "<line x1=\"" << X(g) << "\" y1=\"" << top << "\" x2=\"" << X(g) << "\" y2=\"" << top + ph
      << "\" stroke=\"#c33\" stroke-dasharray=\"6 4\"/>\n<text x=\"" << X(g) + 4 << "\" y=\""
      << (spec.goal_label_low ? top + ph - 6 : top + 14) << "\" fill=\"#c33\">"
      << svg_escape(spec.goal_label) << "</text>\n";
  }
  o << "<text x=\"" << left + pw / 2 << "\" y=\"" << H - 24 << "\" text-anchor=\"middle\">"
    << svg_escape(spec.x_label) << "</text>\n"
    << "<text x=\"22\" y=\"" << top + ph / 2
    << "\" text-anchor=\"middle\" transform=\"rotate(-90 22 " << top + ph / 2 << ")\">"
    << svg_escape(spec.y_label) << "</text>\n";

  // Pareto front of each group (no other point of the group both faster and more accurate).
  std::vector<std::string> fronts;
  for (const ChartPoint& p : pts)
    if (std::find(fronts.begin(), fronts.end(), p.front) == fronts.end()) fronts.push_back(p.front);
  for (const std::string& front : fronts) {
    std::vector<ChartPoint> sorted;
    for (const ChartPoint& p : pts)
      if (p.front == front) sorted.push_back(p);
    std::stable_sort(sorted.begin(), sorted.end(),
                     [](const ChartPoint& a, const ChartPoint& b) { return a.ms < b.ms; });
    std::string path;
    double best_err = 1e300;
    for (const ChartPoint& p : sorted)
      if (p.error_percent < best_err) {
        best_err = p.error_percent;
        path += (path.empty() ? "M" : " L") + std::to_string(X(p.ms)) + " " +
                std::to_string(Y(p.error_percent));
      }
    o << "<path d=\"" << path << "\" fill=\"none\" stroke=\"#999\" stroke-dasharray=\"3 3\"/>\n";
  }

  const char* colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728",
                           "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"};
  std::vector<std::string> series;
  for (const ChartPoint& p : pts)
    if (std::find(series.begin(), series.end(), p.series) == series.end())
      series.push_back(p.series);
  // Circles first, then each label at the first of six spots around its point that overlaps
  // no circle and no label placed so far.
  struct Box {
    double x0, y0, x1, y1;
    bool overlaps(const Box& b) const { return x0 < b.x1 && b.x0 < x1 && y0 < b.y1 && b.y0 < y1; }
  };
  std::vector<Box> taken;
  auto colour_of = [&](const ChartPoint& p) {
    return colours[(std::find(series.begin(), series.end(), p.series) - series.begin()) % 8];
  };
  for (const ChartPoint& p : pts) {
    const double x = X(p.ms), y = Y(p.error_percent);
    o << "<circle cx=\"" << x << "\" cy=\"" << y << "\" r=\"5\" fill=\"" << colour_of(p) << "\"";
    if (above(p)) o << " fill-opacity=\"0\" stroke=\"" << colour_of(p) << "\"";
    if (std::find(spec.ringed.begin(), spec.ringed.end(), p.key) != spec.ringed.end())
      o << " stroke=\"black\" stroke-width=\"2\"";
    o << "><title>" << svg_escape(p.key) << ": " << p.ms << " ms, " << p.error_percent
      << " %</title></circle>\n";
    taken.push_back({x - 5, y - 5, x + 5, y + 5});
  }
  for (const ChartPoint& p : pts) {
    const double x = X(p.ms), y = Y(p.error_percent);
    std::string label = p.label;
    if (above(p)) {
      std::ostringstream e;
      e.precision(2);
      e << " (" << p.error_percent << "%)";
      label += e.str();
    }
    const double w = 6.0 * label.size(), h = 10;
    // Points on the top edge (above error_limit) try below first.
    const double first_dy = above(p) ? 13 : -4, second_dy = above(p) ? -4 : 13;
    const double spots[6][2] = {{7, first_dy}, {7, second_dy}, {-7 - w, -4},
                                {-7 - w, 13},  {8, 4},         {-8 - w, 4}};
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
      << colour_of(p) << "\">" << svg_escape(label) << "</text>\n";
  }
  const double lx = left + pw + 16;
  double ly = top + 10;
  o << "<text x=\"" << lx << "\" y=\"" << ly << "\" font-weight=\"bold\">"
    << svg_escape(spec.legend_title) << "</text>\n";
  for (std::size_t s = 0; s < series.size(); ++s) {
    ly += 20;
    o << "<circle cx=\"" << lx + 6 << "\" cy=\"" << ly - 4 << "\" r=\"5\" fill=\"" << colours[s % 8]
      << "\"/><text x=\"" << lx + 16 << "\" y=\"" << ly << "\">" << svg_escape(series[s])
      << "</text>\n";
  }
  ly += 28;
  std::vector<std::string> notes = {spec.front_note, spec.best_note};
  notes.insert(notes.end(), spec.notes.begin(), spec.notes.end());
  for (std::size_t i = 0; i < notes.size(); ++i)
    o << "<text x=\"" << lx << "\" y=\"" << ly + 16 * static_cast<double>(i) << "\" fill=\"#555\">"
      << svg_escape(notes[i]) << "</text>\n";
  o << "</svg>\n";
  return o.str();
}

std::string line_chart_svg(const LineChartSpec& spec, const std::vector<LineSeries>& series) {
  if (!(spec.x_max > spec.x_min))
    throw std::invalid_argument("line_chart_svg: x_max must be above x_min");
  for (const LineSeries& s : series)
    if (s.x.size() != s.y.size())
      throw std::invalid_argument("line_chart_svg: series '" + s.name +
                                  "' has different numbers of x and y values");
  const double W = kWidth, H = kHeight, left = 80, right = 250, top = 50, bottom = 70;
  const double pw = W - left - right, ph = H - top - bottom;
  std::ostringstream o;
  svg_open(o, spec.title, spec.subtitle, left);
  double ymax_data = 0;
  std::size_t points = 0;
  for (const LineSeries& s : series) {
    points += s.y.size();
    for (double y : s.y) ymax_data = std::max(ymax_data, y);
  }
  if (points == 0) {
    o << "<text x=\"" << left + 20 << "\" y=\"" << top + ph / 2 << "\">"
      << svg_escape(spec.empty_text) << "</text>\n</svg>\n";
    return o.str();
  }
  const double step = round_step(ymax_data);
  const double ymax = std::max(step * std::ceil(ymax_data * 1.08 / step), step);
  const double span = spec.x_max - spec.x_min;
  // Half a tick of margin on both sides, so that the end points' markers stay inside.
  const double margin = 0.04 * span;
  auto X = [&](double x) { return left + (x - spec.x_min + margin) / (span + 2 * margin) * pw; };
  auto Y = [&](double y) { return top + ph - std::clamp(y, 0.0, ymax) / ymax * ph; };

  o << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
    << "\" fill=\"none\" stroke=\"#333\"/>\n";
  const double x_step = std::max(1.0, std::ceil(span / 10));
  for (double v = std::ceil(spec.x_min); v <= spec.x_max + 1e-9; v += x_step) {
    const double x = X(v);
    o << "<line x1=\"" << x << "\" y1=\"" << top << "\" x2=\"" << x << "\" y2=\"" << top + ph
      << "\" stroke=\"#eee\"/>\n<text x=\"" << x << "\" y=\"" << top + ph + 16
      << "\" text-anchor=\"middle\">" << v << "</text>\n";
  }
  for (double e = 0; e <= ymax + 1e-12; e += step) {
    const double y = Y(e);
    o << "<line x1=\"" << left << "\" y1=\"" << y << "\" x2=\"" << left + pw << "\" y2=\"" << y
      << "\" stroke=\"#eee\"/>\n<text x=\"" << left - 6 << "\" y=\"" << y + 4
      << "\" text-anchor=\"end\">" << e << "</text>\n";
  }
  o << "<text x=\"" << left + pw / 2 << "\" y=\"" << H - 24 << "\" text-anchor=\"middle\">"
    << svg_escape(spec.x_label) << "</text>\n"
    << "<text x=\"22\" y=\"" << top + ph / 2
    << "\" text-anchor=\"middle\" transform=\"rotate(-90 22 " << top + ph / 2 << ")\">"
    << svg_escape(spec.y_label) << "</text>\n";

  auto dash_attr = [](const LineSeries& s) {
    const char* d = kDashes[((s.dash % 3) + 3) % 3];
    return *d ? std::string(" stroke-dasharray=\"") + d + "\"" : std::string();
  };
  auto colour = [](const LineSeries& s) { return kPalette[((s.colour % 8) + 8) % 8]; };
  for (const LineSeries& s : series) {
    if (s.x.size() >= 2) {
      o << "<polyline points=\"";
      for (std::size_t i = 0; i < s.x.size(); ++i)
        o << (i ? " " : "") << X(s.x[i]) << "," << Y(s.y[i]);
      o << "\" fill=\"none\" stroke=\"" << colour(s) << "\" stroke-width=\"2\"" << dash_attr(s)
        << "/>\n";
    }
    for (std::size_t i = 0; i < s.x.size(); ++i)
      o << "<circle cx=\"" << X(s.x[i]) << "\" cy=\"" << Y(s.y[i]) << "\" r=\"4\" fill=\""
        << colour(s) << "\"><title>" << svg_escape(s.name) << ": x = " << s.x[i] << ", " << s.y[i]
        << "</title></circle>\n";
  }
  const double lx = left + pw + 16;
  double ly = top + 10;
  o << "<text x=\"" << lx << "\" y=\"" << ly << "\" font-weight=\"bold\">"
    << svg_escape(spec.legend_title) << "</text>\n";
  for (const LineSeries& s : series) {
    ly += 18;
    o << "<line x1=\"" << lx << "\" y1=\"" << ly - 4 << "\" x2=\"" << lx + 24 << "\" y2=\""
      << ly - 4 << "\" stroke=\"" << colour(s) << "\" stroke-width=\"2\"" << dash_attr(s)
      << "/><text x=\"" << lx + 30 << "\" y=\"" << ly << "\">" << svg_escape(s.name) << "</text>\n";
  }
  ly += 28;
  for (std::size_t i = 0; i < spec.notes.size(); ++i)
    o << "<text x=\"" << lx << "\" y=\"" << ly + 16 * static_cast<double>(i) << "\" fill=\"#555\">"
      << svg_escape(spec.notes[i]) << "</text>\n";
  o << "</svg>\n";
  return o.str();
}

}  // namespace penumbra::bench
