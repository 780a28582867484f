#include "file_io.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <system_error>

#include "penumbra/assets/checksum.h"
#include "penumbra/assets/load_error.h"

namespace penumbra::assets {

std::uint64_t fnv1a64(std::span<const unsigned char> bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char b : bytes) {
    h ^= b;
    h *= 0x100000001b3ull;
  }
  return h;
}

}  // namespace penumbra::assets

namespace penumbra::assets::detail {

std::uintmax_t require_file(const std::filesystem::path& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) throw LoadError(path.string(), "no such file");
  if (!std::filesystem::is_regular_file(status))
    throw LoadError(path.string(), "not a regular file");
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw LoadError(path.string(), "cannot read size: " + ec.message());
  if (size == 0) throw LoadError(path.string(), "empty file");
  if (size > kMaxFileBytes)
    throw LoadError(path.string(), "file too large (" + std::to_string(size) + " bytes)");
  return size;
}

std::vector<unsigned char> read_file(const std::filesystem::path& path) {
  const auto size = require_file(path);
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw LoadError(path.string(), "cannot open");
  std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
  const std::size_t got = std::fread(bytes.data(), 1, bytes.size(), f.get());
  if (got != bytes.size()) throw LoadError(path.string(), "read failed");
  return bytes;
}

}  // namespace penumbra::assets::detail

namespace penumbra::assets {

void write_file_atomic(const std::filesystem::path& path, std::span<const unsigned char> bytes) {
  const std::string tmp = path.string() + ".tmp." + std::to_string(::getpid());
  const auto fail = [&](const std::string& what, int err) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path.string() + ": " + what + " (" + std::strerror(err) + ")");
  };
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) fail("cannot create " + tmp, errno);
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size() &&
                       std::fflush(f) == 0 && ::fsync(::fileno(f)) == 0;
  const int write_errno = errno;
  if (std::fclose(f) != 0 || !written) fail("cannot write " + tmp, written ? errno : write_errno);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) fail("cannot rename " + tmp, errno);
}

}  // namespace penumbra::assets
