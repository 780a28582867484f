// Test helpers for the asset loaders: where the shared data lives, scratch directories, files.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "penumbra/assets/checksum.h"
#include "penumbra/assets/load_error.h"

namespace penumbra::assets::test {

inline std::filesystem::path shared_data() {
  return PENUMBRA_SHARED_DATA;
}
inline std::filesystem::path assimp_gltf2() {
  return PENUMBRA_ASSIMP_GLTF2;
}

// A fresh directory under the system temp dir, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "penumbra_assets_XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  std::filesystem::path file(std::string_view name) const { return path_ / name; }
  std::filesystem::path write(std::string_view name, std::string_view bytes) const {
    std::ofstream(file(name), std::ios::binary)
        .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return file(name);
  }

 private:
  std::filesystem::path path_;
};

inline std::string read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Runs `f`, expects a LoadError whose message names `file` and contains `reason`.
template <class F>
void expect_load_error(F&& f, const std::string& file, const std::string& reason) {
  try {
    f();
    ADD_FAILURE() << "no LoadError for " << file << " (expected \"" << reason << "\")";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
  }
}

// Bytes of a file written by our formats, as a string (for text searches in error tests).
inline std::string as_string(const std::vector<unsigned char>& b) {
  return std::string(b.begin(), b.end());
}

// Recomputes the trailing FNV-1a checksum after an edit, so that only the edited field is wrong.
inline std::vector<unsigned char> reseal(std::vector<unsigned char> b) {
  const std::uint64_t h = fnv1a64(std::span<const unsigned char>(b).first(b.size() - 8));
  for (int i = 0; i < 8; ++i)
    b[b.size() - 8 + static_cast<std::size_t>(i)] = static_cast<unsigned char>(h >> (8 * i));
  return b;
}

// Little-endian v at byte `at`.
inline void put_u32(std::vector<unsigned char>& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i)
    b[at + static_cast<std::size_t>(i)] = static_cast<unsigned char>(v >> (8 * i));
}

}  // namespace penumbra::assets::test
