#include "play_record.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <fstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

extern char** environ;

namespace penumbra::play {

FrameSummary summarize(const std::vector<FrameSample>& samples) {
  FrameSummary s;
  if (samples.empty()) return s;
  std::vector<double> wall;
  for (const FrameSample& f : samples) {
    wall.push_back(f.wall_ms);
    s.mean_ms += f.wall_ms;
    s.sim_ms += f.sim_ms;
    s.render_ms += f.render_ms;
  }
  const double n = static_cast<double>(samples.size());
  s.mean_ms /= n;
  s.sim_ms /= n;
  s.render_ms /= n;
  s.fps = 1000.0 / s.mean_ms;
  std::sort(wall.begin(), wall.end());
  auto at = [&](double q) {  // nearest rank
    const auto k = static_cast<std::size_t>(std::ceil(q * n)) - 1;
    return wall[std::min(k, wall.size() - 1)];
  };
  s.median_ms = at(0.5);
  s.p95_ms = at(0.95);
  return s;
}

std::string to_json(const PlayRecord& r) {
  using nlohmann::json;
  const FrameSummary s = summarize(r.samples);
  json j;
  j["format"] = "penumbra-play";
  j["version"] = 1;
  j["date"] = r.date;
  j["machine"] = {{"cpu", r.cpu}, {"cores", r.cores}, {"load_average_start", r.load_average}};
  j["run"] = {{"scene", r.scene},
              {"device", r.device},
              {"width", r.width},
              {"height", r.height},
              {"frames", r.frames},
              {"warmup", r.warmup},
              {"timed_frames", r.samples.size()},
              {"gpu_timed_frames", r.gpu_timed_frames}};
  j["threads"] = {{"simulation", r.sim_threads}, {"lavapipe", r.lavapipe_threads}};
  j["frame"] = {{"fps", s.fps},
                {"mean_ms", s.mean_ms},
                {"median_ms", s.median_ms},
                {"p95_ms", s.p95_ms},
                {"simulation_ms", s.sim_ms},
                {"render_ms", s.render_ms},
                {"gpu_frame_ms", r.gpu_frame_ms},
                {"empty_frame_ms", r.empty_frame_ms},
                {"empty_frame_before_ms", r.empty_frame_before_ms},
                {"empty_frame_after_ms", r.empty_frame_after_ms},
                {"x_empty_frame", r.empty_frame_ms > 0 ? s.median_ms / r.empty_frame_ms : 0.0}};
  j["gpu_pass_ms"] = r.gpu_pass_ms;
  j["terrain"] = {{"lod_pixels", r.terrain_lod_pixels},
                  {"triangles", r.terrain_triangles},
                  {"triangles_full_detail", r.terrain_triangles_full},
                  {"lod_differing_fraction", r.lod_differing_fraction},
                  {"lod_max_difference", r.lod_max_difference}};
  j["lights"] = {{"tiles", r.light_tiles},
                 {"tiles_per_frame", r.light_tiles_per_frame},
                 {"visible_fraction", r.light_visible_fraction},
                 {"worst_observed_relative", r.light_worst_observed},
                 {"worst_deferred_x_threshold", r.light_worst_deferred}};
  j["environment"] = {{"tiles_per_frame", r.environment_tiles_per_frame},
                      {"stale_per_frame", r.environment_stale_per_frame}};
  j["systems"] = json::array();  // done / skipped per frame: null when it does not report
  for (const SystemRow& row : r.systems)
    j["systems"].push_back(
        {{"name", row.name},
         {"mean_ms", row.mean_ms},
         {"max_ms", row.max_ms},
         {"done_per_frame", row.reported ? json(row.done_per_frame) : json(nullptr)},
         {"skipped_per_frame", row.reported ? json(row.skipped_per_frame) : json(nullptr)}});
  j["splits"] = json::array();
  for (const std::string& text : r.splits) {
    json child = json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (!child.is_discarded())
      j["splits"].push_back({{"threads", child["threads"]}, {"frame", child["frame"]}});
  }
  return j.dump(2) + "\n";
}

void describe_machine(PlayRecord& r) {
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);)
    if (line.rfind("model name", 0) == 0) {
      r.cpu = line.substr(line.find(':') + 2);
      break;
    }
  r.cores = static_cast<int>(std::thread::hardware_concurrency());
  std::ifstream load("/proc/loadavg");
  if (!(load >> r.load_average)) r.load_average = -1;
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  r.date = date;
}

int run_child(const std::vector<std::string>& args, const std::string& env) {
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) return -1;
  self[n] = '\0';
  std::vector<std::string> strings;
  strings.emplace_back(self);
  strings.insert(strings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : strings) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::string own_env = env;
  const std::string name = env.substr(0, env.find('='));
  std::vector<char*> envp;
  for (char** e = environ; *e; ++e)
    if (std::string(*e).rfind(name + "=", 0) != 0) envp.push_back(*e);
  envp.push_back(own_env.data());
  envp.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, self, nullptr, nullptr, argv.data(), envp.data()) != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace penumbra::play
