// Shared harness for the Penumbra benchmark groups (ecs, sh, terrain, render, ...).
//
// Each group is one executable; its main() registers the benchmarks and calls run_group()
// (bench_registry.h), which calls run_main() here with the group's summarize function:
//
//   pb::Summary summarize(const pb::Results& r) {
//     pb::Summary s;
//     s.add(...);  // rows computed from r, i.e. from timings measured in this same run
//     return s;
//   }
//
// run_main() runs Google Benchmark normally (every --benchmark_* flag works, including
// --benchmark_out=FILE --benchmark_out_format=json), shows the usual console output while
// capturing every run, then prints a summary table (value, baseline, ratio, goal, PASS/MISS,
// physical floor) to stdout. With --summary_out=PATH (removed from argv before Google Benchmark
// sees it) the same table is also written as JSON to PATH, parent folders created.
//
// Results are looked up by key: the registered name plus "/args" when the benchmark has
// arguments ("/threads:N" when run with ->Threads()); the "/min_time:", "/iterations:",
// "/repeats:" and "/real_time" suffixes are not part of the key. With repetitions, the median
// of the repetitions is used.
//
// The display reporter is always the console reporter: --benchmark_format is not honoured
// for stdout (use --benchmark_out + --benchmark_out_format for machine-readable output).
#pragma once

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace penumbra::bench {

// ---------------------------------------------------------------------------------------------
// Captured results

struct Measurement {
  double real_ns = 0;  // wall-clock time per iteration, nanoseconds
  double cpu_ns = 0;   // CPU time per iteration (main thread), nanoseconds
  std::int64_t iterations = 0;
  std::map<std::string, double> counters;  // finished values, as Google Benchmark reports them
};

class Results {
 public:
  // Key of a run: registered name + "/args" + "/threads:N" (when present).
  static std::string key_of(const benchmark::BenchmarkReporter::Run& run) {
    std::string key = run.run_name.function_name;
    if (!run.run_name.args.empty()) key += "/" + run.run_name.args;
    if (!run.run_name.threads.empty()) key += "/" + run.run_name.threads;
    return key;
  }

  void add(const benchmark::BenchmarkReporter::Run& run) {
    if (run.error_occurred) return;
    Entry& e = entries_[key_of(run)];
    if (run.run_type == benchmark::BenchmarkReporter::Run::RT_Iteration) {
      e.runs.push_back(to_measurement(run));
    } else if (run.aggregate_name == "median" || run.aggregate_name == "mean") {
      // Only used when --benchmark_report_aggregates_only hides the individual runs.
      e.aggregates[run.aggregate_name] = to_measurement(run);
    }
  }

  bool empty() const { return entries_.empty(); }

  // The measurement for `key` (median over repetitions), or nothing if it did not run.
  std::optional<Measurement> get(const std::string& key) const {
    auto it = entries_.find(key);
    if (it == entries_.end()) return std::nullopt;
    const Entry& e = it->second;
    if (e.runs.empty()) {
      for (const char* agg : {"median", "mean"}) {
        if (auto a = e.aggregates.find(agg); a != e.aggregates.end()) return a->second;
      }
      return std::nullopt;
    }
    std::vector<Measurement> runs = e.runs;
    std::sort(runs.begin(), runs.end(),
              [](const Measurement& a, const Measurement& b) { return a.real_ns < b.real_ns; });
    return runs[runs.size() / 2];  // the upper median: an actual run, counters consistent
  }
  std::optional<double> real_ns(const std::string& key) const {
    if (auto m = get(key)) return m->real_ns;
    return std::nullopt;
  }
  std::optional<double> counter(const std::string& key, const std::string& name) const {
    auto m = get(key);
    if (!m) return std::nullopt;
    auto it = m->counters.find(name);
    if (it == m->counters.end()) return std::nullopt;
    return it->second;
  }

 private:
  struct Entry {
    std::vector<Measurement> runs;
    std::map<std::string, Measurement> aggregates;
  };
  static Measurement to_measurement(const benchmark::BenchmarkReporter::Run& run) {
    Measurement m;
    const double to_ns = 1e9 / benchmark::GetTimeUnitMultiplier(run.time_unit);
    m.real_ns = run.GetAdjustedRealTime() * to_ns;
    m.cpu_ns = run.GetAdjustedCPUTime() * to_ns;
    m.iterations = static_cast<std::int64_t>(run.iterations);
    for (const auto& [name, c] : run.counters) m.counters[name] = c.value;
    return m;
  }
  std::map<std::string, Entry> entries_;
};

// What Google Benchmark reported about the machine when the run started.
struct Machine {
  int num_cpus = 0;
  double mhz = 0;
  std::vector<double> load_avg;  // 1, 5, 15 minutes (empty where unavailable)

  std::string text() const {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%d CPUs @ %.0f MHz, load average at start:", num_cpus, mhz);
    std::string out = buf;
    for (double l : load_avg) {
      std::snprintf(buf, sizeof buf, " %.2f", l);
      out += buf;
    }
    // Multi-threaded timings are only meaningful on an otherwise idle machine.
    if (!load_avg.empty() && load_avg[0] > 0.25 * num_cpus) {
      out += "  (busy machine? multi-thread rows are sensitive to other load)";
    }
    return out;
  }
};

// Display reporter: forwards everything to a console reporter and records every run.
class CapturingReporter : public benchmark::BenchmarkReporter {
 public:
  explicit CapturingReporter(Results& results)
      : inner_(isatty(STDOUT_FILENO) ? benchmark::ConsoleReporter::OO_Color
                                     : benchmark::ConsoleReporter::OO_None),
        results_(&results) {}

  bool ReportContext(const Context& context) override {
    machine_.num_cpus = context.cpu_info.num_cpus;
    machine_.mhz = context.cpu_info.cycles_per_second * 1e-6;
    machine_.load_avg = context.cpu_info.load_avg;
    return inner_.ReportContext(context);
  }
  void ReportRuns(const std::vector<Run>& reports) override {
    for (const Run& r : reports) results_->add(r);
    inner_.ReportRuns(reports);
  }
  void Finalize() override { inner_.Finalize(); }

  const Machine& machine() const { return machine_; }

 private:
  benchmark::ConsoleReporter inner_;
  Results* results_;
  Machine machine_;
};

// ---------------------------------------------------------------------------------------------
// Summary rows

struct Goal {
  enum class Metric { kNone, kValue, kRatio };
  enum class Op { kAtLeast, kAtMost };
  Metric metric = Metric::kNone;
  Op op = Op::kAtLeast;
  double target = 0;

  static Goal none() { return {}; }
  static Goal ratio_at_least(double t) { return {Metric::kRatio, Op::kAtLeast, t}; }
  static Goal ratio_at_most(double t) { return {Metric::kRatio, Op::kAtMost, t}; }
  static Goal value_at_least(double t) { return {Metric::kValue, Op::kAtLeast, t}; }
  static Goal value_at_most(double t) { return {Metric::kValue, Op::kAtMost, t}; }

  std::string text() const {
    if (metric == Metric::kNone) return "-";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s%s%g", metric == Metric::kRatio ? "ratio" : "value",
                  op == Op::kAtLeast ? ">=" : "<=", target);
    return buf;
  }
};

struct Row {
  std::string name;
  std::string unit;
  std::optional<double> value;     // measured, in `unit`
  std::optional<double> baseline;  // same unit, measured in the same run
  std::optional<double> ratio;     // as defined by ratio_def (e.g. baseline/value)
  std::string ratio_def;           // e.g. "baseline/value"
  Goal goal;
  std::optional<double> floor;        // physical lower bound on value, same unit
  std::optional<double> floor_ratio;  // value/floor (>= 1 when the floor is a lower bound)
  std::string note;

  // "PASS", "MISS", "INFO" (no goal) or "N/A" (an input did not run).
  std::string status() const {
    if (goal.metric == Goal::Metric::kNone) return value ? "INFO" : "N/A";
    const std::optional<double> m = goal.metric == Goal::Metric::kRatio ? ratio : value;
    if (!m || !std::isfinite(*m)) return "N/A";
    const bool ok = goal.op == Goal::Op::kAtLeast ? *m >= goal.target : *m <= goal.target;
    return ok ? "PASS" : "MISS";
  }
};

// printf's format f applied to one number (the cases' notes).
inline std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

inline std::optional<double> quotient(std::optional<double> a, std::optional<double> b) {
  if (!a || !b || *b == 0) return std::nullopt;
  return *a / *b;
}
inline std::optional<double> scale(std::optional<double> a, double k) {
  if (!a) return std::nullopt;
  return *a * k;
}

class Summary {
 public:
  Row& add(Row row) {
    rows_.push_back(std::move(row));
    return rows_.back();
  }
  // A measured value compared against a baseline, ratio = baseline / value (higher is better
  // for times: the fraction of the baseline's speed reached), floor ratio = value / floor.
  Row& add_vs_baseline(std::string name, std::string unit, std::optional<double> value,
                       std::optional<double> baseline, Goal goal,
                       std::optional<double> floor = std::nullopt, std::string note = {}) {
    Row r;
    r.name = std::move(name);
    r.unit = std::move(unit);
    r.value = value;
    r.baseline = baseline;
    r.ratio = quotient(baseline, value);
    r.ratio_def = "baseline/value";
    r.goal = goal;
    r.floor = floor;
    r.floor_ratio = quotient(value, floor);
    r.note = std::move(note);
    return add(std::move(r));
  }
  const std::vector<Row>& rows() const { return rows_; }

  int count(std::string_view status) const {
    return static_cast<int>(std::count_if(rows_.begin(), rows_.end(),
                                          [&](const Row& r) { return r.status() == status; }));
  }

  void print(std::ostream& out, std::string_view group, const Machine& machine) const {
    std::size_t name_w = 4;
    for (const Row& r : rows_) name_w = std::max(name_w, r.name.size());
    std::string line;
    auto cell = [&](std::string_view s, std::size_t w, bool left = false) {
      std::string c(s);
      if (c.size() < w)
        c = left ? c + std::string(w - c.size(), ' ') : std::string(w - c.size(), ' ') + c;
      line += c;
      line += ' ';
    };
    auto header = [&] {
      line.clear();
      cell("name", name_w, true);
      cell("value", 10);
      cell("unit", 11, true);
      cell("baseline", 10);
      cell("ratio", 8);
      cell("goal", 13);
      cell("status", 6);
      cell("floor", 10);
      cell("val/floor", 9);
      return line;
    };
    const std::string head = header();
    const std::string rule(head.size(), '-');
    out << "\n=== Penumbra benchmark summary: " << group << " ===\n"
        << machine.text() << "\n"
        << head << "\n"
        << rule << "\n";
    for (const Row& r : rows_) {
      line.clear();
      cell(r.name, name_w, true);
      cell(num(r.value), 10);
      cell(r.unit, 11, true);
      cell(num(r.baseline), 10);
      cell(num(r.ratio), 8);
      cell(r.goal.text(), 13);
      cell(r.status(), 6);
      cell(num(r.floor), 10);
      cell(num(r.floor_ratio), 9);
      out << line << "\n";
    }
    out << rule << "\n";
    bool any_note = false;
    for (const Row& r : rows_) {
      if (r.note.empty() && r.ratio_def.empty()) continue;
      if (!any_note) out << "notes:\n";
      any_note = true;
      out << "  " << r.name << ": ";
      if (!r.ratio_def.empty()) out << "ratio = " << r.ratio_def << (r.note.empty() ? "" : "; ");
      out << r.note << "\n";
    }
    out << "PASS " << count("PASS") << ", MISS " << count("MISS") << ", N/A " << count("N/A")
        << ", INFO " << count("INFO") << "\n";
  }

  void write_json(std::ostream& out, std::string_view group, const Machine& machine) const {
    char date[64] = "";
    const std::time_t now = std::time(nullptr);
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%S%z", std::localtime(&now));
    out << "{\n  \"group\": " << quote(group) << ",\n  \"date\": " << quote(date)
        << ",\n  \"num_cpus\": " << machine.num_cpus
        << ",\n  \"mhz_per_cpu\": " << jnum(machine.mhz) << ",\n  \"load_avg\": [";
    for (std::size_t i = 0; i < machine.load_avg.size(); ++i)
      out << (i ? ", " : "") << jnum(machine.load_avg[i]);
    out << "]"
        << ",\n  \"pass\": " << count("PASS") << ",\n  \"miss\": " << count("MISS")
        << ",\n  \"na\": " << count("N/A") << ",\n  \"rows\": [";
    for (std::size_t i = 0; i < rows_.size(); ++i) {
      const Row& r = rows_[i];
      out << (i ? ",\n" : "\n") << "    {\"name\": " << quote(r.name)
          << ", \"unit\": " << quote(r.unit) << ", \"value\": " << jnum(r.value)
          << ", \"baseline\": " << jnum(r.baseline) << ", \"ratio\": " << jnum(r.ratio)
          << ", \"ratio_def\": " << quote(r.ratio_def) << ", \"goal\": ";
      if (r.goal.metric == Goal::Metric::kNone) {
        out << "null";
      } else {
        out << "{\"metric\": " << quote(r.goal.metric == Goal::Metric::kRatio ? "ratio" : "value")
            << ", \"op\": " << quote(r.goal.op == Goal::Op::kAtLeast ? ">=" : "<=")
            << ", \"target\": " << jnum(r.goal.target) << "}";
      }
      out << ", \"status\": " << quote(r.status()) << ", \"floor\": " << jnum(r.floor)
          << ", \"floor_ratio\": " << jnum(r.floor_ratio) << ", \"note\": " << quote(r.note) << "}";
    }
    out << "\n  ]\n}\n";
  }

 private:
  static std::string num(std::optional<double> v) {
    if (!v) return "-";
    char buf[32];
    const double a = std::fabs(*v);
    if (a >= 1e6 || (a < 1e-3 && a > 0)) {
      std::snprintf(buf, sizeof buf, "%.3e", *v);
    } else if (a >= 100) {
      std::snprintf(buf, sizeof buf, "%.1f", *v);
    } else if (a >= 10) {
      std::snprintf(buf, sizeof buf, "%.2f", *v);
    } else {
      std::snprintf(buf, sizeof buf, "%.3f", *v);
    }
    return buf;
  }
  static std::string jnum(std::optional<double> v) {
    if (!v || !std::isfinite(*v)) return "null";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", *v);
    return buf;
  }
  static std::string quote(std::string_view s) {
    std::string out = "\"";
    for (char c : s) {
      switch (c) {
        case '"':
          out += "\\\"";
          break;
        case '\\':
          out += "\\\\";
          break;
        case '\n':
          out += "\\n";
          break;
        case '\t':
          out += "\\t";
          break;
        default:
          if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
          } else {
            out += c;
          }
      }
    }
    return out + "\"";
  }

  std::vector<Row> rows_;
};

// ---------------------------------------------------------------------------------------------
// main()

// Removes "--NAME=VALUE" / "--NAME VALUE" from argv; returns VALUE ("" if absent). For the
// flags a group reads itself (--summary_out here, --records_out and --chart_out in terrain),
// before Google Benchmark sees argv.
inline std::string take_flag(int& argc, char** argv, std::string_view name) {
  std::string value;
  const std::string flag = "--" + std::string(name);
  int w = 1;
  for (int r = 1; r < argc; ++r) {
    const std::string_view a = argv[r];
    if (a.substr(0, flag.size() + 1) == flag + "=") {
      value = std::string(a.substr(flag.size() + 1));
      continue;
    }
    if (a == flag && r + 1 < argc) {
      value = argv[++r];
      continue;
    }
    argv[w++] = argv[r];
  }
  argc = w;
  argv[argc] = nullptr;
  return value;
}

// Runs the registered benchmarks, then prints (and optionally writes) the group's summary,
// built by `summarize` from the results of this run. Returns main()'s exit status.
inline int run_main(int argc, char** argv, std::string_view group,
                    const std::function<Summary(const Results&)>& summarize) {
  const std::string summary_out = take_flag(argc, argv, "summary_out");
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;

  Results results;
  CapturingReporter reporter(results);
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  if (results.empty()) return 0;  // e.g. --benchmark_list_tests, or a filter matching nothing

  const Summary summary = summarize(results);
  summary.print(std::cout, group, reporter.machine());
  std::cout.flush();
  if (!summary_out.empty()) {
    const std::filesystem::path path(summary_out);
    std::error_code ec;
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), ec);
    std::ofstream file(path);
    if (!file) {
      std::cerr << "bench: cannot write --summary_out=" << summary_out << "\n";
      return 1;
    }
    summary.write_json(file, group, reporter.machine());
    std::cout << "summary written to " << summary_out << "\n";
  }
  return 0;
}

}  // namespace penumbra::bench
