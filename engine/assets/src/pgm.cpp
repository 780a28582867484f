// Height maps from files (heightmap.h): the P5 PGM parser, the JSON sidecar, and the mapping of
// samples to a HeightField.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <string>
#include <system_error>
#include <vector>

#include "file_io.h"
#include "penumbra/assets/exr.h"
#include "penumbra/assets/heightmap.h"
#include "penumbra/assets/load_error.h"

namespace penumbra::assets {
namespace {

bool is_pgm_space(unsigned char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

// Header tokenizer for the PGM spec: whitespace and '#' comments (to end of line) between
// tokens, decimal integers only.
class HeaderReader {
 public:
  HeaderReader(std::span<const unsigned char> b, const std::string& name) : b_(b), name_(name) {}

  void skip_space_and_comments() {
    while (pos < b_.size()) {
      if (is_pgm_space(b_[pos])) {
        ++pos;
      } else if (b_[pos] == '#') {
        while (pos < b_.size() && b_[pos] != '\n' && b_[pos] != '\r') ++pos;
      } else {
        break;
      }
    }
  }

  int number(const char* what, int max) {
    skip_space_and_comments();
    if (pos >= b_.size()) throw LoadError(name_, std::string("truncated header: no ") + what);
    if (b_[pos] < '0' || b_[pos] > '9')
      throw LoadError(name_, std::string("bad header: ") + what + " is not a decimal number");
    std::int64_t v = 0;
    while (pos < b_.size() && b_[pos] >= '0' && b_[pos] <= '9') {
      v = v * 10 + (b_[pos++] - '0');
      if (v > max)
        throw LoadError(name_,
                        std::string("bad header: ") + what + " exceeds " + std::to_string(max));
    }
    if (pos < b_.size() && !is_pgm_space(b_[pos]) && b_[pos] != '#')
      throw LoadError(name_, std::string("bad header: garbage after ") + what);
    return static_cast<int>(v);
  }

  std::size_t pos = 0;

 private:
  std::span<const unsigned char> b_;
  const std::string& name_;
};

std::optional<double> number_field(const nlohmann::json& j, const char* key,
                                   const std::string& name) {
  const auto it = j.find(key);
  if (it == j.end()) return std::nullopt;
  if (!it->is_number()) throw LoadError(name, std::string("\"") + key + "\" is not a number");
  const double v = it->get<double>();
  if (!std::isfinite(v)) throw LoadError(name, std::string("\"") + key + "\" is not finite");
  return v;
}

std::optional<int> dimension_field(const nlohmann::json& j, const char* key,
                                   const std::string& name) {
  const auto it = j.find(key);
  if (it == j.end()) return std::nullopt;
  if (!it->is_number_integer() || it->get<std::int64_t>() <= 0 ||
      it->get<std::int64_t>() > (1 << 30))
    throw LoadError(name, std::string("\"") + key + "\" is not a positive integer");
  return static_cast<int>(it->get<std::int64_t>());
}

void require_cell(std::optional<double> v, const char* what, const std::string& name) {
  if (v && !(*v > 0)) throw LoadError(name, std::string(what) + " must be positive");
}

}  // namespace

PgmImage parse_pgm(std::span<const unsigned char> bytes, const std::string& name) {
  if (bytes.empty()) throw LoadError(name, "empty file");
  if (bytes.size() < 2 || bytes[0] != 'P' || bytes[1] != '5')
    throw LoadError(name, "not a binary PGM (magic is not P5)");
  HeaderReader r(bytes, name);
  r.pos = 2;
  if (r.pos < bytes.size() && !is_pgm_space(bytes[r.pos]) && bytes[r.pos] != '#')
    throw LoadError(name, "bad header: garbage after P5");
  PgmImage img;
  img.width = r.number("width", 1 << 30);
  img.height = r.number("height", 1 << 30);
  img.maxval = r.number("maxval", 65535);
  if (img.width == 0 || img.height == 0) throw LoadError(name, "bad header: zero width or height");
  if (img.maxval == 0) throw LoadError(name, "bad header: maxval is 0");
  const std::size_t count = static_cast<std::size_t>(img.width) * img.height;
  if (count > kMaxHeightSamples)
    throw LoadError(name, "image too large (" + std::to_string(img.width) + "x" +
                              std::to_string(img.height) + ")");
  if (r.pos >= bytes.size()) throw LoadError(name, "truncated header: no whitespace after maxval");
  if (!is_pgm_space(bytes[r.pos])) throw LoadError(name, "bad header: no whitespace after maxval");
  ++r.pos;  // exactly one whitespace byte, then the raster
  const std::size_t bps = img.maxval < 256 ? 1 : 2;
  const std::size_t need = count * bps, have = bytes.size() - r.pos;
  if (have < need)
    throw LoadError(name, "truncated: " + std::to_string(have) + " of " + std::to_string(need) +
                              " sample bytes");
  if (have > need)
    throw LoadError(
        name, std::to_string(have - need) + " bytes after the last sample (wrong dimensions?)");
  img.samples.resize(count);
  const unsigned char* p = bytes.data() + r.pos;
  for (std::size_t i = 0; i < count; ++i) {
    const unsigned v = bps == 1 ? p[i] : (unsigned{p[2 * i]} << 8) | p[2 * i + 1];
    if (v > static_cast<unsigned>(img.maxval))
      throw LoadError(name, "sample " + std::to_string(i) + " (" + std::to_string(v) +
                                ") exceeds maxval " + std::to_string(img.maxval));
    img.samples[i] = static_cast<std::uint16_t>(v);
  }
  return img;
}

HeightSidecar parse_height_sidecar(std::string_view text, const std::string& name) {
  nlohmann::json j =
      nlohmann::json::parse(text.begin(), text.end(), nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) throw LoadError(name, "not valid JSON");
  if (!j.is_object()) throw LoadError(name, "not a JSON object");
  HeightSidecar s;
  s.width = dimension_field(j, "width", name);
  s.height = dimension_field(j, "height", name);
  s.min_elevation = number_field(j, "min_elevation", name).value_or(0.0);
  s.elevation_scale = number_field(j, "elevation_scale", name).value_or(1.0);
  s.max_elevation = number_field(j, "max_elevation", name);
  if (const auto c = number_field(j, "cell_size_m", name)) {
    s.cell_size_x = s.cell_size_y = c;
  } else if (const auto it = j.find("suggested_cell_size_m"); it != j.end()) {
    if (!it->is_array() || it->size() != 2 || !(*it)[0].is_number() || !(*it)[1].is_number())
      throw LoadError(name, "\"suggested_cell_size_m\" is not [x, y]");
    s.cell_size_x = (*it)[0].get<double>();
    s.cell_size_y = (*it)[1].get<double>();
  } else if (const auto u = j.find("cell_size_units");
             u != j.end() && u->is_string() && (*u == "m" || *u == "metres" || *u == "meters")) {
    s.cell_size_x = number_field(j, "cell_size_x", name);
    s.cell_size_y = number_field(j, "cell_size_y", name);
    if (!s.cell_size_x) s.cell_size_x = s.cell_size_y;
    if (!s.cell_size_y) s.cell_size_y = s.cell_size_x;
  }
  require_cell(s.cell_size_x, "cell size x", name);
  require_cell(s.cell_size_y, "cell size y", name);
  if (!(s.elevation_scale > 0)) throw LoadError(name, "\"elevation_scale\" must be positive");
  return s;
}

data::HeightField make_height_field(int width, int height, std::span<const float> values,
                              const HeightSidecar& s, const std::string& name) {
  if ((s.width && *s.width != width) || (s.height && *s.height != height))
    throw LoadError(name, "wrong dimensions: image is " + std::to_string(width) + "x" +
                              std::to_string(height) + ", sidecar says " +
                              std::to_string(s.width.value_or(width)) + "x" +
                              std::to_string(s.height.value_or(height)));
  if (values.size() != static_cast<std::size_t>(width) * height)
    throw LoadError(name, "wrong dimensions: " + std::to_string(values.size()) + " values for " +
                              std::to_string(width) + "x" + std::to_string(height));
  data::HeightField f;
  f.width = width;
  f.height = height;
  f.heights.resize(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double h = s.min_elevation + s.elevation_scale * values[i];
    if (!std::isfinite(values[i]) || !std::isfinite(static_cast<float>(h)))
      throw LoadError(name, "NaN or infinite height at sample (" + std::to_string(i % width) +
                                ", " + std::to_string(i / width) + ")");
    if (s.max_elevation && h > *s.max_elevation + 1e-6 * std::abs(*s.max_elevation))
      throw LoadError(name, "height " + std::to_string(h) + " at sample (" +
                                std::to_string(i % width) + ", " + std::to_string(i / width) +
                                ") exceeds max_elevation " + std::to_string(*s.max_elevation));
    f.heights[i] = static_cast<float>(h);
  }
  const double cx = s.cell_size_x.value_or(1.0), cy = s.cell_size_y.value_or(cx);
  f.cell_size = static_cast<float>(std::min(cx, cy));
  f.source = name;
  if (cx == cy) return f;
  // Square cells: resample the coarser axis linearly at the finer spacing.
  const bool along_y = cy > cx;
  const int n = along_y ? height : width;
  const double ratio = along_y ? cy / cx : cx / cy;
  const double md = std::floor((n - 1) * ratio + 1e-9) + 1;
  if (!(md * (along_y ? width : height) <= static_cast<double>(kMaxHeightSamples)))
    throw LoadError(name, "resampled height field too large (cell sizes " + std::to_string(cx) +
                              " x " + std::to_string(cy) + ")");
  const auto m = static_cast<std::int64_t>(md);
  data::HeightField g;
  g.width = along_y ? width : static_cast<int>(m);
  g.height = along_y ? static_cast<int>(m) : height;
  g.cell_size = f.cell_size;
  g.source = name;
  g.heights.resize(static_cast<std::size_t>(g.width) * g.height);
  for (int k = 0; k < m; ++k) {
    const double t = k / ratio;
    const int i0 = std::min(static_cast<int>(t), n - 1), i1 = std::min(i0 + 1, n - 1);
    const float a = static_cast<float>(t - i0);
    if (along_y) {
      for (int x = 0; x < width; ++x) g.at(x, k) = f.at(x, i0) + a * (f.at(x, i1) - f.at(x, i0));
    } else {
      for (int y = 0; y < height; ++y) g.at(k, y) = f.at(i0, y) + a * (f.at(i1, y) - f.at(i0, y));
    }
  }
  return g;
}

HeightSidecar load_height_sidecar(const std::filesystem::path& image_path) {
  std::filesystem::path json = image_path;
  json.replace_extension(".json");
  std::error_code ec;
  if (!std::filesystem::exists(json, ec)) return {};
  const std::vector<unsigned char> bytes = detail::read_file(json);
  return parse_height_sidecar(
      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), json.string());
}

data::HeightField load_height_field_pgm(const std::filesystem::path& path) {
  const std::string name = path.string();
  const std::vector<unsigned char> bytes = detail::read_file(path);
  const PgmImage img = parse_pgm(bytes, name);
  const HeightSidecar sidecar = load_height_sidecar(path);
  const std::vector<float> values(img.samples.begin(), img.samples.end());
  return make_height_field(img.width, img.height, values, sidecar, name);
}

data::HeightField load_height_field(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".pgm") return load_height_field_pgm(path);
  if (ext == ".exr") return load_height_field_exr(path);
  throw LoadError(path.string(), "unknown height map type \"" + ext + "\" (expected .pgm or .exr)");
}

}  // namespace penumbra::assets
