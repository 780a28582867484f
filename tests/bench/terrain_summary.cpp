// The terrain group's summary (terrain_records.h): floors from the same-run baselines, one row
// per main case against its baseline, one row per speed-versus-accuracy point, the baselines
// themselves; the best trade-off; then the records and the chart, when asked for.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "bench_chart.h"
#include "terrain_records.h"

namespace penumbra::terrain_bench {

pb::Summary summarize(const pb::Results& r, const Outputs& out) {
  pb::Summary s;
  const auto peak_ns = r.counter("baseline/peak_ops", "best_ns");
  const auto l3_ns = r.counter("baseline/stream_read_mib/8", "best_ns");
  const auto dram_ns = r.counter("baseline/stream_read_mib/256", "best_ns");
  const std::optional<double> ops_per_ns = pb::quotient(kPeakOpsPerIteration, peak_ns);
  const std::optional<double> l3_bpns = pb::quotient(8.0 * 1024 * 1024, l3_ns);
  const std::optional<double> dram_bpns = pb::quotient(256.0 * 1024 * 1024, dram_ns);

  auto floor_ms = [&](const std::string& key) -> std::optional<double> {
    const auto ops = r.counter(key, "ops");
    const auto bytes = r.counter(key, "bytes");
    if (!ops || !bytes || !ops_per_ns) return std::nullopt;
    const auto bw = *bytes > kL3Bytes ? dram_bpns : l3_bpns;
    double f = *ops / *ops_per_ns;
    if (bw) f = std::max(f, *bytes / *bw);
    return f * 1e-6;
  };
  auto ms = [&](const std::string& key) { return pb::scale(r.real_ns(key), 1e-6); };

  std::vector<Record> records;
  for (const CaseInfo& c : cases()) {
    Record rec{&c, ms(c.key), floor_ms(c.key), std::nullopt, {}};
    if (auto e = errors().find(c.key); e != errors().end()) rec.error = e->second;
    if (rec.ms) records.push_back(rec);
  }

  // Best trade-off: the most accurate chart point within the 10 ms goal; when none meets it,
  // the one with the smallest time x error (the knee of the Pareto front on log-log axes).
  std::string best;
  double best_err = 1e300, best_product = 1e300;
  for (const Record& rec : records) {
    if (!on_chart(rec) || *rec.ms > 10 || *rec.error.rel_rms >= best_err) continue;
    best_err = *rec.error.rel_rms;
    best = rec.info->key;
  }
  if (best.empty())
    for (const Record& rec : records) {
      if (!on_chart(rec) || *rec.ms * *rec.error.rel_rms >= best_product) continue;
      best_product = *rec.ms * *rec.error.rel_rms;
      best = rec.info->key;
    }

  auto goal_of = [](const CaseInfo& c) {
    return c.goal_ms ? pb::Goal::value_at_most(*c.goal_ms) : pb::Goal::none();
  };
  auto err_note = [](const tbr::ErrorSummary& e) {
    if (!e.rel_rms) return std::string();
    char buf[96];
    std::snprintf(buf, sizeof buf, "error rel_rms %.2f%%, max_rel %.1f%%", 100 * *e.rel_rms,
                  100 * e.max_rel.value_or(0));
    return std::string(buf);
  };
  const std::string brute_key = "env/brute_force/256/n_phi:32/bands:4";
  const std::string sweep_key = "env/sweep/256/n_phi:32/bands:4";
  for (const Record& rec : records) {
    const CaseInfo& c = *rec.info;
    if (c.kind != "case") continue;
    std::optional<double> baseline;
    std::string note;
    if (c.is_env && c.key != brute_key && c.size == kSize) {
      baseline = ms(brute_key);
      note = "baseline: brute-force horizons (same update)";
    } else if (c.key == "light/cap/4") {
      baseline = pb::scale(ms("light/cap/1"), 4);
      note = "baseline: 4 x one light (ratio 1 = linear)";
    } else if (c.key == "edit/16x16") {
      baseline = ms(sweep_key);
      note = "baseline: full update (sweep)";
      if (auto p = r.counter(c.key, "pairs"), t = r.counter(c.key, "texels"); p && t)
        note += "; " + std::to_string(static_cast<long>(*p)) + " pairs, " +
                std::to_string(static_cast<long>(*t)) + " texels recomputed";
    } else if (c.key == "shade/rotating_env") {
      baseline = ms("baseline/shade_read_transfer");
      note = "baseline: streaming read of the stored transfer";
    } else if (c.key == "light/cap/1") {
      baseline = ms("light/sh_wedges/1");
      note = "baseline: the thesis's SH-wedge light (same run); thesis GTX 560: ~16 ms per light";
    } else if (c.key == "light/sh_wedges/1") {
      note = "thesis GTX 560: ~16 ms per light";
    } else if (c.size == kBigSize) {
      note = "Timonen 2010 GTX 280: ~43 ms";
    } else if (c.key == "part/horizons/sweep_avx2/n_phi:32") {
      baseline = ms("part/horizons/sweep/n_phi:32");
      note = "baseline: the same sweep on the copy the CPU chose (AVX-512 where it has it)";
    } else if (c.key == "part/pyramid/ls:4") {
      note = "thesis GTX 560: 1.7 ms";
    }
    const std::string en = err_note(rec.error);
    if (!en.empty()) note += (note.empty() ? "" : "; ") + en;
    pb::Row& row =
        s.add_vs_baseline(c.title, "ms", rec.ms, baseline, goal_of(c), rec.floor_ms, note);
    if (!baseline) row.ratio_def.clear();
  }
  for (const Record& rec : records) {
    const CaseInfo& c = *rec.info;
    if (c.kind != "sweep") continue;
    pb::Row& row =
        s.add_vs_baseline("sweep: " + c.env.method + " " + c.env.params_text(), "ms", rec.ms,
                          std::nullopt, pb::Goal::none(), rec.floor_ms, err_note(rec.error));
    row.ratio_def.clear();
  }
  // The machine's moment (vcpu_probe_bench.cpp): each probe's slower vCPU against the one-thread
  // floor (the peak over its threads) and its L2 latency, in the note; the worst probe as the
  // value.
  {
    const auto& labels = vcpu_probe_labels();
    std::string note = "slower vCPU / one-thread floor and its L2 latency, before: ";
    std::optional<double> worst, floor;
    double apart = 1;
    bool one_cpu = false, unpinned = false;
    for (std::size_t i = 0; i < labels.size(); ++i) {
      const std::string key = "probe/vcpu_sweep/" + std::to_string(i);
      const auto a = r.counter(key, "ms0"), b = r.counter(key, "ms1");
      const auto ops = r.counter(key, "ops");
      if (!a || !ops || !ops_per_ns) continue;
      const double ms0 = std::abs(*a), ms1 = b ? std::abs(*b) : ms0;
      one_cpu |= !b;
      unpinned |= *a < 0 || (b && *b < 0);  // negative: that thread could not be pinned
      const double slow = std::max(ms0, ms1);
      const double l2 = (ms1 > ms0 ? r.counter(key, "l2ns1") : r.counter(key, "l2ns0")).value_or(0);
      floor = *ops / (*ops_per_ns / r.counter(key, "peak_threads").value_or(2)) * 1e-6;
      worst = std::max(worst.value_or(0), slow);
      apart = std::max(apart, slow / std::min(ms0, ms1));
      char buf[96];
      std::snprintf(buf, sizeof buf, "%s%s %.1fx %.1f ns", i ? ", " : "", labels[i].c_str(),
                    slow / *floor, l2);
      note += buf;
    }
    char buf[96];
    std::snprintf(buf, sizeof buf, "; the two vCPUs up to %.2fx apart", apart);
    note += one_cpu ? "; one CPU only" : buf;
    if (unpinned) note += " (not pinned)";
    if (worst) {
      pb::Row& row = s.add_vs_baseline("machine moment: one-thread sweep, slower vCPU, worst probe",
                                       "ms", worst, std::nullopt, pb::Goal::none(), floor, note);
      row.ratio_def.clear();
    }
  }
  pb::Row peak;
  peak.name = "vector peak, 2 threads (floor unit)";
  peak.unit = "ops/ns";
  peak.value = ops_per_ns;
  peak.note =
      "AVX2 FMA chains, 8 lanes; an op = one lane of one instruction; best iteration (also the "
      "stream reads)";
  // baselines_bench.cpp: fewer threads seen than the peak ran on means no iteration ran on all.
  const auto seen = r.counter("baseline/peak_ops", "peak_threads_seen");
  const auto threads = r.counter("baseline/peak_ops", "peak_threads");
  if (seen && threads && *seen < *threads)
    peak.note +=
        "; no iteration ran on every thread (a vCPU stopped): the best one's rate per "
        "thread x the threads";
  s.add(peak);
  pb::Row l3;
  l3.name = "stream read 8 MiB (L3), 2 threads";
  l3.unit = "GB/s";
  l3.value = l3_bpns;
  s.add(l3);
  pb::Row dram;
  dram.name = "stream read 256 MiB (DRAM), 2 threads";
  dram.unit = "GB/s";
  dram.value = dram_bpns;
  s.add(dram);

  if (!out.records_path.empty()) {
    if (pb::write_atomically(out.records_path, records_json(records, best)))
      std::cout << "records written to " << out.records_path << "\n";
    else
      std::cerr << "bench_terrain: cannot write " << out.records_path << "\n";
  }
  if (!out.chart_path.empty()) {
    if (pb::write_atomically(out.chart_path, chart_svg(records, best)))
      std::cout << "chart written to " << out.chart_path << "\n";
    else
      std::cerr << "bench_terrain: cannot write " << out.chart_path << "\n";
  }
  if (!best.empty()) std::cout << "best trade-off: " << best << "\n";
  return s;
}

}  // namespace penumbra::terrain_bench
