// The main job, headless: steps the sample world through the job graph and prints a
// per-system timing table. (The Vulkan demo replaces this once the renderer lands.)
//
//   penumbra_play [--frames N] [--threads T] [--particles N] [--trace FILE] [--dot FILE]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "penumbra/components/frame_time.h"
#include "penumbra/game/sample_world.h"
#include "penumbra/jobs/executor.h"
#include "penumbra/jobs/frame_report.h"

namespace {
struct Options {
  int frames = 300;
  int threads = 0;
  std::size_t particles = 200'000;
  std::string trace, dot;
};

[[noreturn]] void usage(const char* error) {
  std::fprintf(stderr,
               "penumbra_play: %s\nusage: penumbra_play [--frames N] [--threads T] [--particles N] "
               "[--trace FILE] [--dot FILE] [--headless]\n",
               error);
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(("missing value after " + a).c_str());
      return argv[++i];
    };
    auto number = [&](long lo) {
      const std::string v = value();
      char* end = nullptr;
      const long n = std::strtol(v.c_str(), &end, 10);
      if (end == v.c_str() || *end != '\0' || n < lo)
        usage((a + " needs an integer >= " + std::to_string(lo) + ", got '" + v + "'").c_str());
      return n;
    };
    if (a == "--frames")
      o.frames = static_cast<int>(number(1));
    else if (a == "--threads")
      o.threads = static_cast<int>(number(0));
    else if (a == "--particles")
      o.particles = static_cast<std::size_t>(number(0));
    else if (a == "--trace")
      o.trace = value();
    else if (a == "--dot")
      o.dot = value();
    else if (a == "--headless") {
    }  // always headless until the renderer lands
    else
      usage(("unknown option " + a).c_str());
  }
  return o;
}

bool write_file(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary);
    if (!(f << text)) return false;
  }
  return std::rename(tmp.c_str(), path.c_str()) == 0;  // atomic replace
}
}  // namespace

int main(int argc, char** argv) {
  using namespace penumbra;
  const Options opt = parse(argc, argv);

  ecs::World world;
  game::SampleWorldConfig config;
  config.particles = opt.particles;
  game::populate_sample_world(world, config);
  jobs::Schedule schedule;
  game::add_sample_systems(schedule);
  jobs::Executor executor(opt.threads);
  executor.set_trace_tasks(!opt.trace.empty());

  jobs::TimingTable table;
  std::vector<jobs::FrameStats> traced;
  const int warmup = opt.frames > 10 ? 5 : 0;
  for (int f = 0; f < opt.frames; ++f) {
    const jobs::FrameStats& stats = executor.run(schedule, world);
    if (f >= warmup) table.add(stats);
    if (!opt.trace.empty() && f >= opt.frames - 3) traced.push_back(stats);
  }

  std::printf("penumbra: headless sample world, %zu entities, %d frames (%d warm-up), %d threads\n",
              world.size(), opt.frames, warmup, executor.threads());
  table.print(std::cout);
  if (!opt.trace.empty()) {
    if (!write_file(opt.trace, jobs::chrome_trace_json(traced))) {
      std::fprintf(stderr, "penumbra_play: cannot write trace to %s\n", opt.trace.c_str());
      return 1;
    }
    std::printf("trace (Perfetto / chrome://tracing): %s\n", opt.trace.c_str());
  }
  if (!opt.dot.empty()) {
    if (!write_file(opt.dot, schedule.to_dot())) {
      std::fprintf(stderr, "penumbra_play: cannot write graph to %s\n", opt.dot.c_str());
      return 1;
    }
    std::printf("job graph (Graphviz DOT): %s\n", opt.dot.c_str());
  }
  return 0;
}
