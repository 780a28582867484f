#include "penumbra/assets/probe_points.h"

#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <system_error>

#include "file_io.h"
#include "penumbra/assets/load_error.h"
#include "penumbra/assets/probe_cloud_file.h"
#include "penumbra/data/probe_cloud.h"

namespace penumbra::assets {
namespace {

// Whitespace inside a line (a newline ends the line, not a token).
bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// A token shown in a message: at most 32 characters.
std::string shown(std::string_view token) {
  return token.size() <= 32 ? std::string(token) : std::string(token.substr(0, 32)) + "...";
}

}  // namespace

ProbePoints parse_probe_points(std::string_view text, int bands, const std::string& name) {
  if (bands < data::kProbeMinBands || bands > data::kProbeMaxBands)
    throw std::invalid_argument("probe points: bands " + std::to_string(bands) + " outside " +
                                std::to_string(data::kProbeMinBands) + ".." +
                                std::to_string(data::kProbeMaxBands));
  const std::size_t sh_count = static_cast<std::size_t>(3 * bands * bands);
  ProbePoints out;
  std::vector<float> values;
  std::size_t line_no = 0;
  int with_sh = -1;  // unknown until the first probe line; then 0 or 1
  std::size_t first_line = 0;
  while (!text.empty()) {
    ++line_no;
    const std::size_t eol = text.find('\n');
    std::string_view line = text.substr(0, eol);
    text = eol == std::string_view::npos ? std::string_view() : text.substr(eol + 1);
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    const auto fail = [&](const std::string& reason) {
      throw LoadError(name, "line " + std::to_string(line_no) + ": " + reason);
    };
    values.clear();
    std::size_t at = 0;
    while (true) {
      while (at < line.size() && is_blank(line[at])) ++at;
      if (at == line.size()) break;
      std::size_t end = at;
      while (end < line.size() && !is_blank(line[end])) ++end;
      const std::string_view token = line.substr(at, end - at);
      at = end;
      // from_chars takes no leading '+'; a plain text file may well have one.
      const std::string_view digits =
          token.size() > 1 && token[0] == '+' && token[1] != '-' ? token.substr(1) : token;
      double v = 0;
      const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
      if (ptr != digits.data() + digits.size() ||
          (ec != std::errc() && ec != std::errc::result_out_of_range))
        fail(std::string("'").append(shown(token)).append("' is not a number"));
      const auto bad_value = [&](const char* what) {
        // Appended, not "literal" + string&&: GCC 12 warns falsely there (-Wrestrict, bug 105329).
        std::string m = "value ";
        m += std::to_string(values.size() + 1);
        m += " ('";
        m += shown(token);
        m += "') ";
        m += what;
        fail(m);
      };
      if (ec == std::errc::result_out_of_range) bad_value("is outside the float range");
      if (!std::isfinite(v)) bad_value("is not finite");
      if (std::abs(v) > std::numeric_limits<float>::max()) bad_value("is outside the float range");
      values.push_back(static_cast<float>(v));
    }
    if (values.empty()) continue;
    if (values.size() != 3 && values.size() != 3 + sh_count)
      fail(std::to_string(values.size()) + " values (expected x y z, or x y z and " +
           std::to_string(sh_count) + " SH coefficients for " + std::to_string(bands) + " bands)");
    const int has_sh = values.size() > 3 ? 1 : 0;
    if (with_sh < 0) {
      with_sh = has_sh;
      first_line = line_no;
    } else if (has_sh != with_sh) {
      fail(std::string(has_sh ? "SH coefficients" : "no SH coefficients") + ", but line " +
           std::to_string(first_line) + (with_sh ? " has them" : " has none") +
           " (every line or none)");
    }
    if (out.positions.size() >= kMaxProbeCloudProbes)
      fail("more than " + std::to_string(kMaxProbeCloudProbes) + " points");
    out.positions.emplace_back(values[0], values[1], values[2]);
    out.sh.insert(out.sh.end(), values.begin() + 3, values.end());
  }
  return out;
}

ProbePoints load_probe_points(const std::filesystem::path& path, int bands) {
  const std::vector<unsigned char> bytes = detail::read_file(path);
  return parse_probe_points(
      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), bands,
      path.string());
}

}  // namespace penumbra::assets
