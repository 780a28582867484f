#include "file_io.h"

#include <cstdio>
#include <memory>
#include <string>
#include <system_error>

#include "penumbra/assets/load_error.h"

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
