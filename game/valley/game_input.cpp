#include "penumbra/game/game_input.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "penumbra/assets/atomic_write.h"
#include "penumbra/assets/checksum.h"
#include "penumbra/assets/load_error.h"

namespace penumbra::game {
namespace {

std::uint64_t checksum(std::string_view payload) {
  return assets::fnv1a64({reinterpret_cast<const unsigned char*>(payload.data()), payload.size()});
}

// Reads one unsigned or signed decimal field followed by `sep`; false on anything else.
template <class T>
bool field(std::string_view& s, T& out, char sep) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  if (ec != std::errc() || end == s.data() || end == s.data() + s.size() || *end != sep)
    return false;
  s.remove_prefix(static_cast<std::size_t>(end - s.data()) + 1);
  return true;
}

}  // namespace

std::int8_t quantize_axis(float v) {
  if (!(v == v)) return 0;
  return static_cast<std::int8_t>(std::lround(std::clamp(v, -1.0f, 1.0f) * 127.0f));
}

std::string encode_input_recording(const InputRecording& r) {
  if (r.steps.size() > kMaxInputSteps)
    throw std::invalid_argument("input recording: " + std::to_string(r.steps.size()) +
                                " steps, more than " + std::to_string(kMaxInputSteps));
  std::string payload;
  for (std::size_t i = 0; i < r.steps.size();) {
    std::size_t j = i + 1;
    while (j < r.steps.size() && r.steps[j] == r.steps[i]) ++j;
    const GameInput& s = r.steps[i];
    if (s.move_x < -127 || s.move_y < -127 || s.turn < -127 || s.buttons > 31)
      throw std::invalid_argument("input recording: step " + std::to_string(i) +
                                  " out of range (axes -127..127, buttons 0..31)");
    char line[64];
    std::snprintf(line, sizeof line, "%zu %d %d %d %d\n", j - i, s.move_x, s.move_y, s.turn,
                  s.buttons);
    payload += line;
    i = j;
  }
  char header[96];
  std::snprintf(header, sizeof header, "%s %u %zu %016llx\n", kInputMagic.data(), kInputVersion,
                payload.size(), static_cast<unsigned long long>(checksum(payload)));
  return header + payload;
}

InputRecording parse_input_recording(std::string_view bytes, const std::string& file) {
  auto fail = [&](const std::string& reason) -> InputRecording {
    throw assets::LoadError(file, reason);
  };
  if (bytes.empty()) return fail("empty file");
  const std::size_t eol = bytes.find('\n');
  if (eol == std::string_view::npos || eol > 80) return fail("no header line");
  std::string_view h = bytes.substr(0, eol + 1);
  if (!h.starts_with(kInputMagic) || h.size() <= kInputMagic.size() || h[kInputMagic.size()] != ' ')
    return fail("not an input recording (magic '" + std::string(kInputMagic) + "' missing)");
  h.remove_prefix(kInputMagic.size() + 1);
  std::uint32_t version = 0;
  std::size_t length = 0;
  if (!field(h, version, ' ')) return fail("bad version field");
  if (version != kInputVersion)
    return fail("version " + std::to_string(version) + ", this build reads " +
                std::to_string(kInputVersion));
  if (!field(h, length, ' ')) return fail("bad length field");
  if (h.size() != 17 || h.back() != '\n') return fail("bad checksum field");
  std::uint64_t sum = 0;
  const auto [end, ec] = std::from_chars(h.data(), h.data() + 16, sum, 16);
  if (ec != std::errc() || end != h.data() + 16) return fail("bad checksum field");
  const std::string_view payload = bytes.substr(eol + 1);
  if (payload.size() < length)
    return fail("truncated: " + std::to_string(payload.size()) + " of " + std::to_string(length) +
                " payload bytes");
  if (payload.size() > length)
    return fail(std::to_string(payload.size() - length) + " bytes after the payload");
  if (checksum(payload) != sum) return fail("checksum mismatch (the file is corrupt)");

  InputRecording r;
  std::string_view s = payload;
  for (std::size_t line = 1; !s.empty(); ++line) {
    std::size_t count = 0;
    int mx = 0, my = 0, turn = 0, buttons = 0;
    if (!field(s, count, ' ') || !field(s, mx, ' ') || !field(s, my, ' ') || !field(s, turn, ' ') ||
        !field(s, buttons, '\n'))
      return fail("line " + std::to_string(line) + ": expected '<count> <x> <y> <turn> <buttons>'");
    if (count < 1 || count > (1u << 24) || mx < -127 || mx > 127 || my < -127 || my > 127 ||
        turn < -127 || turn > 127 || buttons < 0 || buttons > 31)
      return fail("line " + std::to_string(line) + ": value out of range");
    if (r.steps.size() + count > kMaxInputSteps)
      return fail("more than " + std::to_string(kMaxInputSteps) + " steps");
    const GameInput in{static_cast<std::int8_t>(mx), static_cast<std::int8_t>(my),
                       static_cast<std::int8_t>(turn), static_cast<std::uint8_t>(buttons)};
    r.steps.insert(r.steps.end(), count, in);
  }
  return r;
}

InputRecording load_input_recording(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw assets::LoadError(file.string(), "cannot open");
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  return parse_input_recording(bytes, file.string());
}

void save_input_recording(const InputRecording& recording, const std::filesystem::path& file) {
  assets::write_file_atomic(file, encode_input_recording(recording));
}

}  // namespace penumbra::game
