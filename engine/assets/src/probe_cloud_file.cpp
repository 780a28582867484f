#include "penumbra/assets/probe_cloud_file.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "byte_io.h"
#include "file_io.h"
#include "penumbra/assets/load_error.h"
#include "penumbra/data/finite.h"

namespace penumbra::assets {
namespace {

using detail::get_f32;
using detail::get_i32;
using detail::get_u32;
using detail::get_u64;

constexpr unsigned char kCloudMagic[4] = {'P', 'C', 'L', 'D'};
constexpr std::size_t kCloudHeaderBytes = 24;
constexpr std::size_t kCellBytes = 32 + 64;  // indices + transform
using detail::kChecksumBytes;

bool bands_ok(std::int64_t bands) {
  return bands >= data::kProbeMinBands && bands <= data::kProbeMaxBands;
}

std::string bands_problem(std::int64_t bands) {
  return "bands " + std::to_string(bands) + " outside " + std::to_string(data::kProbeMinBands) +
         ".." + std::to_string(data::kProbeMaxBands);
}

// The header's counts: "" when within the caps and consistent.
std::string count_problem(std::uint64_t probes, std::uint64_t cells, std::uint64_t inner) {
  if (probes > kMaxProbeCloudProbes)
    return "too many probes (" + std::to_string(probes) + ", at most " +
           std::to_string(kMaxProbeCloudProbes) + ")";
  if (cells > kMaxProbeCloudCells)
    return "too many cells (" + std::to_string(cells) + ", at most " +
           std::to_string(kMaxProbeCloudCells) + ")";
  if (inner > cells)
    return "inner count " + std::to_string(inner) + " above the cell count " +
           std::to_string(cells);
  return {};
}

using data::finite;

// Everything both the writer and the reader require of the contents (array sizes agree, which
// the reader's layout guarantees); "" when valid.
std::string cloud_problem(const data::ProbeCloud& c) {
  if (!bands_ok(c.bands)) return bands_problem(c.bands);
  const std::size_t n = c.positions.size();
  const std::size_t cells = c.cells.size();
  if (std::string p = count_problem(n, cells, c.inner_count); !p.empty()) return p;
  if (c.sh.size() != n * c.coeffs_per_probe())
    return "SH size " + std::to_string(c.sh.size()) + " is not " +
           std::to_string(c.coeffs_per_probe()) + " per probe for " + std::to_string(n) + " probes";
  if (c.hull_normals.size() != n)
    return std::to_string(c.hull_normals.size()) + " hull normals for " + std::to_string(n) +
           " probes";
  if (c.transforms.size() != cells)
    return std::to_string(c.transforms.size()) + " transforms for " + std::to_string(cells) +
           " cells";
  for (std::size_t i = 0; i < n; ++i) {
    if (!finite(c.positions[i])) return "probe " + std::to_string(i) + ": non-finite position";
    if (!finite(c.hull_normals[i]))
      return "probe " + std::to_string(i) + ": non-finite hull normal";
  }
  for (std::size_t i = 0; i < c.sh.size(); ++i)
    if (!std::isfinite(c.sh[i]))
      return "probe " + std::to_string(i / c.coeffs_per_probe()) + ": non-finite SH coefficient";
  const auto probes = static_cast<std::int64_t>(n);
  const auto cell_count = static_cast<std::int64_t>(cells);
  for (std::size_t i = 0; i < cells; ++i) {
    const data::ProbeCell& cell = c.cells[i];
    const auto which = [i] { return "cell " + std::to_string(i) + ": "; };  // messages only
    const bool outer = cell.outer();
    if (i < c.inner_count && outer)
      return which() + "outer cell among the inner ones (inner count " +
             std::to_string(c.inner_count) + ")";
    if (i >= c.inner_count && !outer)
      return which() + "inner tetrahedron after the outer cells (inner count " +
             std::to_string(c.inner_count) + ")";
    for (int k = 0; k < (outer ? 3 : 4); ++k) {
      const std::int32_t v = cell.vertices[static_cast<std::size_t>(k)];
      if (v < 0 || v >= probes)
        return which() + "vertex " + std::to_string(v) + " out of range (" + std::to_string(n) +
               " probes)";
    }
    for (std::int32_t nb : cell.neighbours)
      if (nb < 0 || nb >= cell_count)
        return which() + "neighbour " + std::to_string(nb) + " out of range (" +
               std::to_string(cells) + " cells)";
    const glm::mat4& m = c.transforms[i];
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 4; ++row)
        if (!std::isfinite(m[col][row])) return which() + "non-finite transform";
  }
  return {};
}

}  // namespace

std::uint64_t probe_cloud_file_size(int bands, std::uint64_t probes, std::uint64_t cells) {
  const auto b2 = static_cast<std::uint64_t>(bands) * static_cast<std::uint64_t>(bands);
  return kCloudHeaderBytes + probes * (24 + 12 * b2) + kCellBytes * cells + kChecksumBytes;
}

std::vector<unsigned char> encode_probe_cloud_file(const data::ProbeCloud& cloud) {
  if (const std::string p = cloud_problem(cloud); !p.empty())
    throw std::invalid_argument("probe cloud file: " + p);
  std::vector<unsigned char> out(static_cast<std::size_t>(
      probe_cloud_file_size(cloud.bands, cloud.positions.size(), cloud.cells.size())));
  detail::ByteWriter w{out};
  w.bytes(kCloudMagic, 4);
  w.u32(kProbeCloudFileVersion);
  w.u32(static_cast<std::uint32_t>(cloud.bands));
  w.u32(static_cast<std::uint32_t>(cloud.positions.size()));
  w.u32(static_cast<std::uint32_t>(cloud.cells.size()));
  w.u32(cloud.inner_count);
  for (const glm::vec3& p : cloud.positions)
    for (int k = 0; k < 3; ++k) w.f32(p[k]);
  for (float f : cloud.sh) w.f32(f);
  for (const glm::vec3& nrm : cloud.hull_normals)
    for (int k = 0; k < 3; ++k) w.f32(nrm[k]);
  for (const data::ProbeCell& cell : cloud.cells) {
    for (std::int32_t v : cell.vertices) w.i32(v);
    for (std::int32_t nb : cell.neighbours) w.i32(nb);
  }
  for (const glm::mat4& m : cloud.transforms)
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 4; ++row) w.f32(m[col][row]);
  w.u64(fnv1a64(std::span<const unsigned char>(out).first(w.at)));
  return out;
}

data::ProbeCloud parse_probe_cloud_file(std::span<const unsigned char> bytes,
                                        const std::string& name) {
  const auto fail = [&](const std::string& reason) { throw LoadError(name, reason); };
  if (bytes.size() < 8) fail("truncated: " + std::to_string(bytes.size()) + " bytes, no header");
  if (std::memcmp(bytes.data(), kCloudMagic, 4) != 0)
    fail("not a probe cloud file (magic is not PCLD)");
  const std::uint32_t version = get_u32(bytes.data() + 4);
  if (version != kProbeCloudFileVersion)
    fail("unsupported version " + std::to_string(version) + " (expected " +
         std::to_string(kProbeCloudFileVersion) + ")");
  if (bytes.size() < kCloudHeaderBytes)
    fail("truncated: " + std::to_string(bytes.size()) + " of " + std::to_string(kCloudHeaderBytes) +
         " header bytes");
  const std::uint32_t bands = get_u32(bytes.data() + 8);
  const std::uint32_t n = get_u32(bytes.data() + 12);
  const std::uint32_t cells = get_u32(bytes.data() + 16);
  const std::uint32_t inner = get_u32(bytes.data() + 20);
  if (!bands_ok(bands)) fail(bands_problem(bands));
  if (std::string p = count_problem(n, cells, inner); !p.empty()) fail(p);
  const std::uint64_t expected = probe_cloud_file_size(static_cast<int>(bands), n, cells);
  if (bytes.size() < expected)
    fail("truncated: " + std::to_string(bytes.size()) + " of " + std::to_string(expected) +
         " bytes for " + std::to_string(n) + " probes and " + std::to_string(cells) + " cells");
  if (bytes.size() > expected)
    fail(std::to_string(bytes.size() - expected) + " trailing bytes after the checksum");
  const std::uint64_t stored = get_u64(bytes.data() + expected - kChecksumBytes);
  if (stored != fnv1a64(bytes.first(static_cast<std::size_t>(expected) - kChecksumBytes)))
    fail("checksum mismatch");

  data::ProbeCloud c;
  c.bands = static_cast<int>(bands);
  c.inner_count = inner;
  const unsigned char* p = bytes.data() + kCloudHeaderBytes;
  const auto vec3 = [&p] {
    const glm::vec3 v(get_f32(p), get_f32(p + 4), get_f32(p + 8));
    p += 12;
    return v;
  };
  c.positions.resize(n);
  for (glm::vec3& v : c.positions) v = vec3();
  c.sh.resize(std::size_t{n} * c.coeffs_per_probe());
  for (float& f : c.sh) {
    f = get_f32(p);
    p += 4;
  }
  c.hull_normals.resize(n);
  for (glm::vec3& v : c.hull_normals) v = vec3();
  c.cells.resize(cells);
  for (data::ProbeCell& cell : c.cells) {
    for (std::int32_t& v : cell.vertices) {
      v = get_i32(p);
      p += 4;
    }
    for (std::int32_t& nb : cell.neighbours) {
      nb = get_i32(p);
      p += 4;
    }
  }
  c.transforms.resize(cells);
  for (glm::mat4& m : c.transforms)
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 4; ++row) {
        m[col][row] = get_f32(p);
        p += 4;
      }
  if (const std::string reason = cloud_problem(c); !reason.empty()) fail(reason);
  return c;
}

data::ProbeCloud load_probe_cloud_file(const std::filesystem::path& path) {
  const std::vector<unsigned char> bytes = detail::read_file(path);
  return parse_probe_cloud_file(bytes, path.string());
}

void save_probe_cloud_file(const std::filesystem::path& path, const data::ProbeCloud& cloud) {
  detail::write_file_atomic(path, encode_probe_cloud_file(cloud));
}

}  // namespace penumbra::assets
