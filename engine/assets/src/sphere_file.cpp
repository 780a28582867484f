#include "penumbra/assets/sphere_file.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "byte_io.h"
#include "file_io.h"
#include "penumbra/assets/load_error.h"

namespace penumbra::assets {
namespace {

constexpr unsigned char kSphereMagic[4] = {'P', 'S', 'P', 'H'};
constexpr std::size_t kSphereHeaderBytes = 36;  // up to and including the name length
constexpr std::size_t kSphereBytes = 20;
using detail::kChecksumBytes;

using detail::ByteWriter;
using detail::get_u32;
using detail::get_u64;

// Everything both the writer and the reader require of the contents; "" when valid.
std::string sphere_problem(const SphereSetFile& set) {
  if (set.spheres.size() > kMaxSphereFileSpheres)
    return "too many spheres (" + std::to_string(set.spheres.size()) + ", at most " +
           std::to_string(kMaxSphereFileSpheres) + ")";
  if (set.source_model.size() > kMaxSphereFileName)
    return "source model name too long (" + std::to_string(set.source_model.size()) + " bytes)";
  if (set.source_model.find('\0') != std::string::npos) return "source model name contains NUL";
  const auto m = static_cast<std::uint32_t>(set.method);
  if (m > static_cast<std::uint32_t>(SphereFitMethod::kVariational))
    return "unknown fit method " + std::to_string(m);
  if (!std::isfinite(set.outside_volume_ratio) || set.outside_volume_ratio < -1.0)
    return "outside volume ratio not finite or below -1";
  if (!std::isfinite(set.coverage) || set.coverage < 0.0 || set.coverage > 1.0)
    return "coverage not finite or outside [0, 1]";
  const auto n = static_cast<std::int64_t>(set.spheres.size());
  for (std::int64_t i = 0; i < n; ++i) {
    const data::Sphere& s = set.spheres[static_cast<std::size_t>(i)];
    const std::string which = "sphere " + std::to_string(i) + ": ";
    if (!std::isfinite(s.centre.x) || !std::isfinite(s.centre.y) || !std::isfinite(s.centre.z))
      return which + "non-finite centre";
    if (!std::isfinite(s.radius)) return which + "non-finite radius";
    if (s.radius < 0) return which + "negative radius";
    if (s.parent < -1 || s.parent >= n || s.parent == i)
      return which + "parent " + std::to_string(s.parent) + " out of range";
  }
  // Parent chains must end at a root: walk each chain once (0 new, 1 on the walk, 2 done).
  std::vector<unsigned char> state(set.spheres.size(), 0);
  std::vector<std::int32_t> walk;
  for (std::size_t i = 0; i < set.spheres.size(); ++i) {
    walk.clear();
    std::int32_t j = static_cast<std::int32_t>(i);
    while (j >= 0 && state[static_cast<std::size_t>(j)] == 0) {
      state[static_cast<std::size_t>(j)] = 1;
      walk.push_back(j);
      j = set.spheres[static_cast<std::size_t>(j)].parent;
    }
    if (j >= 0 && state[static_cast<std::size_t>(j)] == 1)
      return "sphere " + std::to_string(j) + ": cyclic parent chain";
    for (std::int32_t k : walk) state[static_cast<std::size_t>(k)] = 2;
  }
  return {};
}

}  // namespace

const char* sphere_fit_method_name(SphereFitMethod method) {
  switch (method) {
    case SphereFitMethod::kNone:
      return "none";
    case SphereFitMethod::kKMeans:
      return "kmeans";
    case SphereFitMethod::kVariational:
      return "variational";
  }
  return "unknown";
}

std::vector<unsigned char> encode_sphere_file(const SphereSetFile& set) {
  if (const std::string p = sphere_problem(set); !p.empty())
    throw std::invalid_argument("sphere file: " + p);
  std::vector<unsigned char> out(kSphereHeaderBytes + set.source_model.size() +
                                 kSphereBytes * set.spheres.size() + kChecksumBytes);
  ByteWriter w{out};
  w.bytes(kSphereMagic, 4);
  w.u32(kSphereFileVersion);
  w.u32(static_cast<std::uint32_t>(set.spheres.size()));
  w.u32(static_cast<std::uint32_t>(set.method));
  w.u64(std::bit_cast<std::uint64_t>(set.outside_volume_ratio));
  w.u64(std::bit_cast<std::uint64_t>(set.coverage));
  w.u32(static_cast<std::uint32_t>(set.source_model.size()));
  w.bytes(set.source_model.data(), set.source_model.size());
  for (const data::Sphere& s : set.spheres) {
    for (float f : {s.centre.x, s.centre.y, s.centre.z, s.radius})
      w.u32(std::bit_cast<std::uint32_t>(f));
    w.u32(std::bit_cast<std::uint32_t>(s.parent));
  }
  w.u64(fnv1a64(std::span<const unsigned char>(out).first(w.at)));
  return out;
}

SphereSetFile parse_sphere_file(std::span<const unsigned char> bytes, const std::string& name) {
  const auto fail = [&](const std::string& reason) { throw LoadError(name, reason); };
  if (bytes.size() < 8) fail("truncated: " + std::to_string(bytes.size()) + " bytes, no header");
  if (std::memcmp(bytes.data(), kSphereMagic, 4) != 0)
    fail("not a sphere file (magic is not PSPH)");
  const std::uint32_t version = get_u32(bytes.data() + 4);
  if (version != kSphereFileVersion)
    fail("unsupported version " + std::to_string(version) + " (expected " +
         std::to_string(kSphereFileVersion) + ")");
  if (bytes.size() < kSphereHeaderBytes)
    fail("truncated: " + std::to_string(bytes.size()) + " of " +
         std::to_string(kSphereHeaderBytes) + " header bytes");
  const std::uint32_t count = get_u32(bytes.data() + 8);
  const std::uint32_t name_len = get_u32(bytes.data() + 32);
  if (count > kMaxSphereFileSpheres)
    fail("too many spheres (" + std::to_string(count) + ", at most " +
         std::to_string(kMaxSphereFileSpheres) + ")");
  if (name_len > kMaxSphereFileName)
    fail("source model name too long (" + std::to_string(name_len) + " bytes)");
  const std::size_t expected =
      kSphereHeaderBytes + name_len + kSphereBytes * std::size_t{count} + kChecksumBytes;
  if (bytes.size() < expected)
    fail("truncated: " + std::to_string(bytes.size()) + " of " + std::to_string(expected) +
         " bytes for " + std::to_string(count) + " spheres");
  if (bytes.size() > expected)
    fail(std::to_string(bytes.size() - expected) + " trailing bytes after the checksum");
  const std::uint64_t stored = get_u64(bytes.data() + expected - kChecksumBytes);
  if (stored != fnv1a64(bytes.first(expected - kChecksumBytes))) fail("checksum mismatch");

  SphereSetFile set;
  set.method = static_cast<SphereFitMethod>(get_u32(bytes.data() + 12));
  set.outside_volume_ratio = std::bit_cast<double>(get_u64(bytes.data() + 16));
  set.coverage = std::bit_cast<double>(get_u64(bytes.data() + 24));
  set.source_model.assign(reinterpret_cast<const char*>(bytes.data() + kSphereHeaderBytes),
                          name_len);
  set.spheres.resize(count);
  const unsigned char* p = bytes.data() + kSphereHeaderBytes + name_len;
  for (data::Sphere& s : set.spheres) {
    s.centre.x = std::bit_cast<float>(get_u32(p));
    s.centre.y = std::bit_cast<float>(get_u32(p + 4));
    s.centre.z = std::bit_cast<float>(get_u32(p + 8));
    s.radius = std::bit_cast<float>(get_u32(p + 12));
    s.parent = std::bit_cast<std::int32_t>(get_u32(p + 16));
    p += kSphereBytes;
  }
  if (const std::string reason = sphere_problem(set); !reason.empty()) fail(reason);
  return set;
}

SphereSetFile load_sphere_file(const std::filesystem::path& path) {
  const std::vector<unsigned char> bytes = detail::read_file(path);
  return parse_sphere_file(bytes, path.string());
}

void write_sphere_file(const std::filesystem::path& path, const SphereSetFile& set) {
  detail::write_file_atomic(path, encode_sphere_file(set));
}

}  // namespace penumbra::assets
