// OpenEXR loaders (exr.h), on OpenEXR 3.1's scanline/tiled InputFile.
#include "penumbra/assets/exr.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <numbers>
#include <string>
#include <vector>

#include "file_io.h"
#include "penumbra/assets/heightmap.h"
#include "penumbra/assets/load_error.h"

namespace penumbra::assets {
namespace {

struct Window {
  int width = 0, height = 0;
};

Window checked_window(const Imf::Header& header, const std::string& name) {
  const Imath::Box2i dw = header.dataWindow();
  const std::int64_t w = std::int64_t{dw.max.x} - dw.min.x + 1;
  const std::int64_t h = std::int64_t{dw.max.y} - dw.min.y + 1;
  if (w <= 0 || h <= 0) throw LoadError(name, "empty data window");
  if (static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) > kMaxExrTexels)
    throw LoadError(name, "image too large (" + std::to_string(w) + "x" + std::to_string(h) + ")");
  return {static_cast<int>(w), static_cast<int>(h)};
}

// Reads `channels` (all present, full resolution) as float, interleaved with `stride` floats
// per texel starting at out[offset].
void read_channels(Imf::InputFile& file, const std::vector<const char*>& channels,
                   std::vector<float>& out, std::size_t stride, const std::string& name) {
  const Imath::Box2i dw = file.header().dataWindow();
  Imf::FrameBuffer fb;
  for (std::size_t c = 0; c < channels.size(); ++c) {
    const Imf::Channel* ch = file.header().channels().findChannel(channels[c]);
    if (ch == nullptr) throw LoadError(name, std::string("no channel ") + channels[c]);
    if (ch->xSampling != 1 || ch->ySampling != 1)
      throw LoadError(name, std::string("channel ") + channels[c] + " is subsampled");
    fb.insert(channels[c], Imf::Slice::Make(Imf::FLOAT, out.data() + c, dw, stride * sizeof(float),
                                            0, 1, 1, 0.0, false, false));
  }
  file.setFrameBuffer(fb);
  file.readPixels(dw.min.y, dw.max.y);
}

void require_finite(const std::vector<float>& v, std::size_t stride, int width,
                    const std::string& name) {
  std::size_t bad = 0, first = 0;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]) && bad++ == 0) first = i / stride;
  if (bad > 0)
    throw LoadError(name, std::to_string(bad) + " NaN or infinite values, first at texel (" +
                              std::to_string(first % width) + ", " + std::to_string(first / width) +
                              ")");
}

// See exr.h. Row weights are the equirect texel solid angles up to a constant factor.
std::size_t remove_negative_lobes(data::EnvironmentMap& m) {
  constexpr int kBlock = 8;
  std::vector<double> w(static_cast<std::size_t>(m.height));
  for (int y = 0; y < m.height; ++y)
    w[static_cast<std::size_t>(y)] =
        std::cos(std::numbers::pi * y / m.height) - std::cos(std::numbers::pi * (y + 1) / m.height);
  std::size_t clamped = 0;
  for (int by = 0; by < m.height; by += kBlock)
    for (int bx = 0; bx < m.width; bx += kBlock)
      for (int c = 0; c < 3; ++c) {
        const int ey = std::min(by + kBlock, m.height), ex = std::min(bx + kBlock, m.width);
        double pos = 0, neg = 0;
        for (int y = by; y < ey; ++y)
          for (int x = bx; x < ex; ++x) {
            const float v = m.rgb[3 * (static_cast<std::size_t>(y) * m.width + x) + c];
            (v < 0 ? neg : pos) += w[static_cast<std::size_t>(y)] * v;
          }
        if (neg == 0) continue;
        const float scale = pos + neg > 0 ? static_cast<float>((pos + neg) / pos) : 0.0f;
        for (int y = by; y < ey; ++y)
          for (int x = bx; x < ex; ++x) {
            float& v = m.rgb[3 * (static_cast<std::size_t>(y) * m.width + x) + c];
            clamped += v < 0;
            v = v < 0 ? 0.0f : v * scale;
          }
      }
  return clamped;
}

}  // namespace

int exr_channel_count(const std::filesystem::path& path) {
  detail::require_file(path);
  try {
    Imf::InputFile file(path.c_str());
    int count = 0;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it)
      ++count;
    return count;
  } catch (const std::exception& e) {
    throw LoadError(path.string(), std::string("OpenEXR: ") + e.what());
  }
}

data::EnvironmentMap load_environment_map(const std::filesystem::path& path) {
  const std::string name = path.string();
  detail::require_file(path);
  data::EnvironmentMap map;
  try {
    Imf::InputFile file(path.c_str());
    const Window win = checked_window(file.header(), name);
    const auto& list = file.header().channels();
    const bool rgb = list.findChannel("R") && list.findChannel("G") && list.findChannel("B");
    if (!rgb && !list.findChannel("Y")) throw LoadError(name, "no R, G, B or Y channels");
    map.width = win.width;
    map.height = win.height;
    map.rgb.assign(static_cast<std::size_t>(win.width) * win.height * 3, 0.0f);
    if (rgb) {
      read_channels(file, {"R", "G", "B"}, map.rgb, 3, name);
    } else {
      read_channels(file, {"Y"}, map.rgb, 3, name);
      for (std::size_t i = 0; i < map.rgb.size(); i += 3)
        map.rgb[i + 1] = map.rgb[i + 2] = map.rgb[i];
    }
  } catch (const LoadError&) {
    throw;
  } catch (const std::exception& e) {
    throw LoadError(name, std::string("OpenEXR: ") + e.what());
  }
  require_finite(map.rgb, 3, map.width, name);
  map.clamped_values = remove_negative_lobes(map);
  map.source = name;
  return map;
}

data::HeightField load_height_field_exr(const std::filesystem::path& path) {
  const std::string name = path.string();
  detail::require_file(path);
  const HeightSidecar sidecar = load_height_sidecar(path);
  std::vector<float> values;
  Window win;
  try {
    Imf::InputFile file(path.c_str());
    win = checked_window(file.header(), name);
    const auto& list = file.header().channels();
    std::string channels;
    int count = 0;
    for (auto it = list.begin(); it != list.end(); ++it, ++count)
      channels += (count ? ", " : "") + std::string(it.name());
    if (count != 1)
      throw LoadError(name, "a height map needs exactly one channel, found " +
                                std::to_string(count) + (count ? " (" + channels + ")" : ""));
    values.assign(static_cast<std::size_t>(win.width) * win.height, 0.0f);
    read_channels(file, {list.begin().name()}, values, 1, name);
  } catch (const LoadError&) {
    throw;
  } catch (const std::exception& e) {
    throw LoadError(name, std::string("OpenEXR: ") + e.what());
  }
  return make_height_field(win.width, win.height, values, sidecar, name);
}

}  // namespace penumbra::assets
