// DDS transport figures for mcvio::dds versus bare Fast DDS (issue 2).
//
// For a sensor_msgs/Image (752x480 mono8) and a sensor_msgs/Imu, over three transports (in-process,
// shared memory to a child process, UDP on loopback to a child process) it measures
//   latency:    ping-pong round trip / 2 (the echo end sends every ping straight back): p50, p99;
//   throughput: bursts under the lossless QoS (reliable, keep all: the writer waits for the
//               reader), msgs/s and payload MB/s from the first write to the end-of-burst ack, and
//               the CPU time both processes spent per message;
// each with the wrapper (Node::createPublisher/createSubscription) and with a bare DataWriter/
// DataReader on the same generated types and the same QoS, alternating ping by ping and burst by
// burst so that load from other processes on a shared machine hits both alike. A first pair of rows
// times the publish call alone (no reader): the wrapper's own cost without transport noise.
//
// Run: dds_benchmark [--udp_profile=FILE] [--domain=N] [--bare_participant=shared|own]
//                    [Google Benchmark flags]
//   --udp_profile       Fast DDS XML with participant profile "localhost_udp" (default: the
//                       repository's config/dds/localhost_udp.xml)
//   --bare_participant  shared (default): bare endpoints use the wrapper's DomainParticipant, so
//                       both share threads and transports and only the code path differs;
//                       own: a second participant with the same participant QoS.
#include <benchmark/benchmark.h>
#include <fastrtps/config.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "bare_qos.hpp"
#include "probe_rig.hpp"

namespace mcvio::dds::bench {
namespace {

constexpr const char* kApiNames[2] = {"wrapper", "bare"};
constexpr std::chrono::milliseconds kPingTimeout{5000};
constexpr std::chrono::milliseconds kBurstTimeout{30000};
constexpr double kLatencyBudgetSeconds = 4.0;     // per row, both APIs together
constexpr double kThroughputBudgetSeconds = 4.0;  // per row, both APIs together

/// One row of the final table: a transport and a message, both APIs.
struct Figures {
  bool latency = false, throughput = false;
  double p50_us[2] = {0, 0}, p99_us[2] = {0, 0};
  double stalled_pct[2] = {0, 0};  ///< pings slower than 10x the median of both APIs
  std::size_t pings[2] = {0, 0};
  int timeouts[2] = {0, 0};
  double msgs_per_s[2] = {0, 0}, mb_per_s[2] = {0, 0}, cpu_us_per_msg[2] = {0, 0};
  std::size_t bursts[2] = {0, 0};
  double rate_overhead_pct = 0, cpu_overhead_pct = 0;  ///< medians over burst pairs
  std::size_t payload_bytes = 0;
};
std::vector<std::pair<std::string, Figures>> g_figures;

/// publish() versus DataWriter::write() with no reader.
struct PublishCall {
  std::string label;
  double wrapper_ns, bare_ns, overhead_ns;
};
std::vector<PublishCall> g_publish_call;

Figures& figuresFor(Transport transport, const char* label) {
  const std::string key = std::string(transportName(transport)) + "|" + label;
  for (auto& [k, f] : g_figures) {
    if (k == key) return f;
  }
  g_figures.emplace_back(key, Figures{});
  return g_figures.back().second;
}

std::int64_t threadCpuNs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

double secondsSince(std::int64_t start_ns) {
  return static_cast<double>(steadyNowNs() - start_ns) * 1e-9;
}

/// Nearest-rank percentile of `v` (sorted in place).
double percentile(std::vector<double>& v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
}

double overheadPct(double wrapper, double bare) {
  return bare > 0 ? (wrapper - bare) / bare * 100.0 : std::nan("");
}

std::string loadAverage() {
  std::ifstream f("/proc/loadavg");
  std::string a, b, c;
  f >> a >> b >> c;
  return a + " " + b + " " + c;
}

/// Writes until the prober accepts `msg`, for up to a minute as the wrapper's publish() does. A
/// keep-all DataWriter::write under flow control returns false after at most max_blocking_time
/// (1 s), often much sooner, when the writer's history is still full.
template <class T>
bool sendPatiently(Prober<T>& prober, const T& msg, int* blocked) {
  const std::int64_t start = steadyNowNs();
  while (!prober.send(msg)) {
    ++*blocked;
    if (secondsSince(start) > 60.0) return false;
  }
  return true;
}

/// One ping-pong; `one_way_us` is half the round trip.
template <class T>
bool pingOnce(Prober<T>& prober, T& msg, std::uint32_t seq, std::chrono::milliseconds timeout,
              double* one_way_us) {
  msg.header().stamp().nanosec(seq);
  int blocked = 0;
  const std::int64_t sent = steadyNowNs();
  if (!sendPatiently(prober, msg, &blocked)) return false;
  PongMonitor::Pong pong;
  if (!prober.monitor().waitFor(seq, timeout, &pong)) return false;
  *one_way_us = static_cast<double>(pong.arrival_ns - sent) * 1e-3 / 2.0;
  return true;
}

/// Pings until the echo answers (discovery and matching done both ways), then a few more so pools
/// and caches are warm. False when no echo came within 20 s.
template <class T>
bool connect(Prober<T>& prober, T& msg, std::uint32_t& seq) {
  const std::int64_t start = steadyNowNs();
  double us = 0;
  while (!pingOnce(prober, msg, ++seq, std::chrono::milliseconds(250), &us)) {
    if (secondsSince(start) > 20.0) return false;
  }
  for (int i = 0; i < 20; ++i) pingOnce(prober, msg, ++seq, kPingTimeout, &us);
  return true;
}

template <class T>
std::unique_ptr<ProbeRig<T>> connectedRig(benchmark::State& state, Transport transport,
                                          const BusConfig& bus, T& ping, std::uint32_t seq[2]) {
  std::unique_ptr<ProbeRig<T>> rig;
  try {
    rig = std::make_unique<ProbeRig<T>>(transport, bus);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return nullptr;
  }
  ping.header().frame_id(kPingFrame);
  for (int api = 0; api < 2; ++api) {
    if (!connect(rig->prober(api), ping, seq[api])) {
      const std::string why = std::string("no echo for the ") + kApiNames[api] +
                              " prober within 20 s" +
                              (rig->echoProcessExited() ? " (the echo process exited)" : "");
      state.SkipWithError(why.c_str());
      return nullptr;
    }
  }
  return rig;
}

template <class T>
void latencyRow(benchmark::State& state, Transport transport, const BusConfig& bus) {
  using M = BenchMessage<T>;
  T ping = M::make();
  std::uint32_t seq[2] = {0, 0};
  auto rig = connectedRig(state, transport, bus, ping, seq);
  if (!rig) return;
  std::vector<double> one_way[2];
  int timeouts[2] = {0, 0};
  for (auto _ : state) {
    const std::int64_t start = steadyNowNs();
    // Alternate every ping (wrapper-bare, bare-wrapper, ...): on a shared machine the load changes
    // from one millisecond to the next, and both APIs must see the same load.
    for (int round = 0; secondsSince(start) < kLatencyBudgetSeconds; ++round) {
      if (one_way[0].size() >= static_cast<std::size_t>(M::kMaxPings) &&
          one_way[1].size() >= static_cast<std::size_t>(M::kMaxPings)) {
        break;
      }
      for (int k = 0; k < 2; ++k) {
        const int api = (round + k) % 2;
        double us = 0;
        if (pingOnce(rig->prober(api), ping, ++seq[api], kPingTimeout, &us)) {
          one_way[api].push_back(us);
        } else {
          ++timeouts[api];
        }
      }
    }
  }
  Figures& f = figuresFor(transport, M::kLabel);
  f.latency = true;
  f.payload_bytes = serializedSize(ping);
  // On a loaded machine about 1% of pings wait for a CPU for a scheduler slice (milliseconds), so
  // a p99 lands on either side of that step by chance. The share of such stalls (10x the pooled
  // median) compares the tails more steadily.
  std::vector<double> pooled = one_way[0];
  pooled.insert(pooled.end(), one_way[1].begin(), one_way[1].end());
  const double stall_us = 10.0 * percentile(pooled, 0.5);
  for (int api = 0; api < 2; ++api) {
    const auto stalls = std::count_if(one_way[api].begin(), one_way[api].end(),
                                      [&](double us) { return us > stall_us; });
    f.stalled_pct[api] =
        one_way[api].empty() ? 0.0 : 100.0 * static_cast<double>(stalls) / one_way[api].size();
    state.counters[std::string(kApiNames[api]) + "_stalled_pct"] = f.stalled_pct[api];
  }
  for (int api = 0; api < 2; ++api) {
    f.pings[api] = one_way[api].size();
    f.timeouts[api] = timeouts[api];
    f.p50_us[api] = percentile(one_way[api], 0.50);
    f.p99_us[api] = percentile(one_way[api], 0.99);
    state.counters[std::string(kApiNames[api]) + "_p50_us"] = f.p50_us[api];
    state.counters[std::string(kApiNames[api]) + "_p99_us"] = f.p99_us[api];
  }
  state.counters["p50_overhead_pct"] = overheadPct(f.p50_us[0], f.p50_us[1]);
  state.counters["p99_overhead_pct"] = overheadPct(f.p99_us[0], f.p99_us[1]);
  state.counters["pings_per_api"] = static_cast<double>(std::min(f.pings[0], f.pings[1]));
  state.counters["timeouts"] = timeouts[0] + timeouts[1];
}

/// What one throughput burst cost.
struct Burst {
  double wall_s = 0;             ///< first write to the ack's arrival
  double probe_cpu_s = 0;        ///< CPU of this (measuring) process during the burst
  std::int64_t echo_cpu_ns = 0;  ///< the echo process's CPU clock at its ack (0 in-process)
  bool count_ok = false;         ///< the echo counted exactly what was sent
};

/// One burst of `burst` messages, the last one asking for an ack with the echo's running count.
template <class T>
bool burstOnce(Prober<T>& prober, T& msg, std::uint32_t seq, int burst, std::int32_t expected_count,
               int* blocked, Burst* result) {
  msg.header().frame_id(kStreamFrame);
  const std::int64_t start = steadyNowNs();
  const std::int64_t cpu_start = processCpuNs();
  for (int i = 0; i + 1 < burst; ++i) {
    if (!sendPatiently(prober, msg, blocked)) return false;
  }
  msg.header().frame_id(kStreamEndFrame);
  msg.header().stamp().nanosec(seq);
  if (!sendPatiently(prober, msg, blocked)) return false;
  PongMonitor::Pong pong;
  if (!prober.monitor().waitFor(seq, kBurstTimeout, &pong)) return false;
  result->wall_s = static_cast<double>(pong.arrival_ns - start) * 1e-9;
  result->probe_cpu_s = static_cast<double>(processCpuNs() - cpu_start) * 1e-9;
  result->echo_cpu_ns = pong.echo_cpu_ns;
  result->count_ok = pong.count == expected_count;
  return true;
}

double median(std::vector<double> v) { return percentile(v, 0.5); }

template <class T>
void throughputRow(benchmark::State& state, Transport transport, const BusConfig& bus) {
  using M = BenchMessage<T>;
  T msg = M::make();
  std::uint32_t seq[2] = {0, 0};
  auto rig = connectedRig(state, transport, bus, msg, seq);
  if (!rig) return;
  const bool echo_in_child = transport != Transport::kInProcess;
  std::vector<double> rate[2], cpu_us_per_msg[2];
  // Overheads from the two bursts of each pair, which ran back to back under the same load.
  std::vector<double> paired_rate_overhead, paired_cpu_overhead;
  std::int32_t sent[2] = {0, 0};
  std::size_t measured[2] = {0, 0};
  double measured_seconds[2] = {0, 0};
  int blocked = 0, failed = 0, miscounted = 0;
  std::int64_t last_echo_cpu_ns = -1;
  for (auto _ : state) {
    const std::int64_t start = steadyNowNs();
    // Pair 0 warms up and gives the echo's first CPU reading; it is not counted.
    for (int pair = 0;
         pair < M::kMaxBurstPairs && (pair < 3 || secondsSince(start) < kThroughputBudgetSeconds);
         ++pair) {
      double pair_rate[2] = {0, 0}, pair_cpu[2] = {0, 0};
      for (int k = 0; k < 2; ++k) {
        const int api = (pair + k) % 2;  // who goes first alternates
        Burst b;
        if (!burstOnce(rig->prober(api), msg, ++seq[api], M::kBurst, sent[api] + M::kBurst,
                       &blocked, &b)) {
          ++failed;
          last_echo_cpu_ns = -1;
          continue;
        }
        sent[api] += M::kBurst;
        if (!b.count_ok) ++miscounted;
        // The echo end is idle between bursts, so its CPU clock between two consecutive acks is
        // what this burst cost it.
        const double echo_cpu_s = echo_in_child && last_echo_cpu_ns >= 0
                                      ? static_cast<double>(b.echo_cpu_ns - last_echo_cpu_ns) * 1e-9
                                      : 0.0;
        const bool have_echo_cpu = !echo_in_child || last_echo_cpu_ns >= 0;
        last_echo_cpu_ns = b.echo_cpu_ns;
        if (pair == 0 || !have_echo_cpu) continue;
        pair_rate[api] = M::kBurst / b.wall_s;
        pair_cpu[api] = (b.probe_cpu_s + echo_cpu_s) * 1e6 / M::kBurst;
        rate[api].push_back(pair_rate[api]);
        cpu_us_per_msg[api].push_back(pair_cpu[api]);
        measured[api] += M::kBurst;
        measured_seconds[api] += b.wall_s;
      }
      if (pair_rate[0] > 0 && pair_rate[1] > 0) {
        paired_rate_overhead.push_back(-overheadPct(pair_rate[0], pair_rate[1]));
        paired_cpu_overhead.push_back(overheadPct(pair_cpu[0], pair_cpu[1]));
      }
    }
  }
  Figures& f = figuresFor(transport, M::kLabel);
  f.throughput = true;
  f.payload_bytes = serializedSize(msg);
  for (int api = 0; api < 2; ++api) {
    // All measured messages over all their bursts' time: with bursts interleaved, both APIs see
    // the same mix of load, which a per-burst median (bimodal under load) does not guarantee.
    f.msgs_per_s[api] = measured_seconds[api] > 0 ? measured[api] / measured_seconds[api] : 0.0;
    f.mb_per_s[api] = f.msgs_per_s[api] * static_cast<double>(f.payload_bytes) * 1e-6;
    f.cpu_us_per_msg[api] = median(cpu_us_per_msg[api]);
    f.bursts[api] = rate[api].size();
    const std::string name = kApiNames[api];
    state.counters[name + "_msgs_s"] = f.msgs_per_s[api];
    state.counters[name + "_MB_s"] = f.mb_per_s[api];
    state.counters[name + "_cpu_us_msg"] = f.cpu_us_per_msg[api];
  }
  f.rate_overhead_pct = median(paired_rate_overhead);
  f.cpu_overhead_pct = median(paired_cpu_overhead);
  state.counters["rate_overhead_pct"] = f.rate_overhead_pct;
  state.counters["cpu_overhead_pct"] = f.cpu_overhead_pct;
  state.counters["msgs_per_api"] = static_cast<double>(std::min(measured[0], measured[1]));
  state.counters["failed_bursts"] = failed;
  // Writes that gave up after the keep-all max_blocking_time (1 s) and were retried here. The
  // wrapper retries inside publish() for up to 60 s, so these are in practice bare writes.
  state.counters["writes_retried"] = blocked;
  if (miscounted > 0)
    state.SkipWithError("the echo counted a different number of messages than were sent");
}

/// The publish call alone, with no reader matched: what Publisher::publish adds to
/// DataWriter::write (serialization into the writer history included in both), without any
/// transport noise.
template <class T>
void publishCallRow(benchmark::State& state, const BusConfig& bus) {
  using M = BenchMessage<T>;
  using PubSubType = typename interfaces::RosType<T>::PubSubType;
  const std::string topic = std::string("/dds_bench/") + M::kKey + "/solo";
  const std::string bare_topic = std::string("dds_bench_bare/") + M::kKey + "/solo";
  std::shared_ptr<Participant> participant;
  std::shared_ptr<Node> node;
  std::unique_ptr<Publisher<T>> publisher;
  std::unique_ptr<BareParticipant> bare_participant;
  eprosima::fastdds::dds::DataWriter* bare_writer = nullptr;
  try {
    participant = Participant::create(
        wrapperParticipantOptions(bus, Transport::kInProcess, "dds_bench_solo"));
    node = participant->createNode("dds_bench_solo");
    publisher = node->createPublisher<T>(topic, QosProfile::defaults());
    bare_participant =
        makeBareParticipant(bus, Transport::kInProcess, *participant, "dds_bench_bare_solo");
    bare_writer = bare_participant->publisher()->create_datawriter(
        bare_participant->topic(bare_topic, eprosima::fastdds::dds::TypeSupport(new PubSubType())),
        bareWriterQos<T>(QosProfile::defaults()));
    if (!bare_writer) throw std::runtime_error("Fast DDS could not create the bare writer");
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  T msg = M::make();
  const int block = std::is_same_v<T, Image> ? 20 : 500;
  std::vector<double> ns_per_call[2], paired;
  int failed = 0;
  for (auto _ : state) {
    const std::int64_t start = steadyNowNs();
    for (int round = 0; round < 2000 && (round < 20 || secondsSince(start) < 1.5); ++round) {
      double per_call[2] = {0, 0};
      for (int k = 0; k < 2; ++k) {
        const int api = (round + k) % 2;
        // Thread CPU time: a block preempted by another process on the shared cores still counts
        // only the calls' own work.
        const std::int64_t t0 = threadCpuNs();
        for (int i = 0; i < block; ++i) {
          const bool ok = api == 0 ? publisher->publish(msg) : bare_writer->write(&msg);
          if (!ok) ++failed;
        }
        per_call[api] = static_cast<double>(threadCpuNs() - t0) / block;
      }
      if (round < 2) continue;  // warm-up: history and payload pool grow to their working size
      for (int api = 0; api < 2; ++api) ns_per_call[api].push_back(per_call[api]);
      paired.push_back(per_call[0] - per_call[1]);
    }
  }
  bare_participant->publisher()->delete_datawriter(bare_writer);
  const double wrapper_ns = median(ns_per_call[0]), bare_ns = median(ns_per_call[1]);
  g_publish_call.push_back({M::kLabel, wrapper_ns, bare_ns, median(paired)});
  state.counters["wrapper_ns"] = wrapper_ns;
  state.counters["bare_ns"] = bare_ns;
  state.counters["overhead_ns"] = median(paired);
  state.counters["overhead_pct"] = median(paired) / bare_ns * 100.0;
  state.counters["failed"] = failed;
}

template <class T>
void registerRows(Transport transport, const BusConfig& bus) {
  const std::string suffix = std::string(transportName(transport)) + "/" + BenchMessage<T>::kKey;
  benchmark::RegisterBenchmark(
      ("latency/" + suffix).c_str(),
      [transport, bus](benchmark::State& s) { latencyRow<T>(s, transport, bus); })
      ->Iterations(1)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark(
      ("throughput/" + suffix).c_str(),
      [transport, bus](benchmark::State& s) { throughputRow<T>(s, transport, bus); })
      ->Iterations(1)
      ->Unit(benchmark::kMillisecond);
}

void printTable(const std::string& load_before, const std::string& load_after) {
  if (g_figures.empty() && g_publish_call.empty()) return;
  std::printf("\nFast DDS %s. Pings and streams: lossless QoS (reliable, keep all <= 100);\n",
              FASTRTPS_VERSION_STR);
  std::printf("pongs: reliable, keep last 10. Load average before: %s, after: %s\n",
              load_before.c_str(), load_after.c_str());
  if (!g_figures.empty()) {
    std::printf(
        "Latency = ping-pong round trip / 2; stalled = pings over 10x the median of both APIs.\n");
    std::printf("msgs/s = measured messages / their bursts' time (first write to the ack).\n");
    std::printf("CPU = CPU time of both processes per message during the bursts.\n");
    std::printf(
        "Overhead = wrapper vs bare (+ = wrapper slower or costlier): latency from the two\n");
    std::printf("p50s/p99s; msgs/s and CPU as the median over wrapper/bare burst pairs.\n\n");
    std::printf(
        "| transport | message | bytes | API | p50 us | p99 us | stalled %% | pings | msgs/s |");
    std::printf(" MB/s | CPU us/msg | bursts |\n");
    std::printf("|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const auto& [key, f] : g_figures) {
      const std::string transport = key.substr(0, key.find('|'));
      const std::string label = key.substr(key.find('|') + 1);
      for (int api = 0; api < 2; ++api) {
        std::printf(
            "| %s | %s | %zu | %s | %.1f | %.1f | %.2f | %zu | %.0f | %.1f | %.2f | %zu |\n",
            transport.c_str(), label.c_str(), f.payload_bytes, kApiNames[api], f.p50_us[api],
            f.p99_us[api], f.stalled_pct[api], f.pings[api], f.msgs_per_s[api], f.mb_per_s[api],
            f.cpu_us_per_msg[api], f.bursts[api]);
      }
    }
    std::printf("\n| transport | message | p50 latency overhead %% | p99 latency overhead %% |");
    std::printf(" msgs/s overhead %% | CPU/msg overhead %% |\n");
    std::printf("|---|---|---:|---:|---:|---:|\n");
    for (const auto& [key, f] : g_figures) {
      std::printf("| %s | %s | %+.1f | %+.1f | %+.1f | %+.1f |\n",
                  key.substr(0, key.find('|')).c_str(), key.substr(key.find('|') + 1).c_str(),
                  overheadPct(f.p50_us[0], f.p50_us[1]), overheadPct(f.p99_us[0], f.p99_us[1]),
                  f.rate_overhead_pct, f.cpu_overhead_pct);
    }
  }
  if (!g_publish_call.empty()) {
    std::printf(
        "\n| publish call, no reader | wrapper CPU ns | bare CPU ns | overhead ns (paired median) "
        "|");
    std::printf(" overhead %% |\n");
    std::printf("|---|---:|---:|---:|---:|\n");
    for (const auto& c : g_publish_call) {
      std::printf("| %s | %.0f | %.0f | %+.1f | %+.2f |\n", c.label.c_str(), c.wrapper_ns,
                  c.bare_ns, c.overhead_ns, c.overhead_ns / c.bare_ns * 100.0);
    }
  }
}

bool takeFlag(const char* arg, const char* name, std::string* value) {
  const std::size_t n = std::strlen(name);
  if (std::strncmp(arg, name, n) != 0 || arg[n] != '=') return false;
  *value = arg + n + 1;
  return true;
}

}  // namespace
}  // namespace mcvio::dds::bench

int main(int argc, char** argv) {
  using namespace mcvio::dds::bench;
  if (argc >= 2 && std::strcmp(argv[1], "--echo") == 0) return runEchoProcess(argc, argv);

  BusConfig bus;
  // A domain of its own (201..232) keeps the figures apart from test processes on domains 100..199.
  bus.domain_id = 201 + static_cast<int>(getpid() % 32);
  bus.udp_profiles_file = MCVIO_DDS_BENCH_UDP_PROFILE;
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i) {
    std::string value;
    if (takeFlag(argv[i], "--udp_profile", &value)) {
      bus.udp_profiles_file = value;
    } else if (takeFlag(argv[i], "--domain", &value)) {
      bus.domain_id = std::stoi(value);
    } else if (takeFlag(argv[i], "--bare_participant", &value) &&
               (value == "shared" || value == "own")) {
      bus.bare_in_own_participant = value == "own";
    } else {
      args.push_back(argv[i]);
    }
  }
  int n = static_cast<int>(args.size());
  benchmark::Initialize(&n, args.data());
  if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;
  for (const char* key : {BenchMessage<Imu>::kKey, BenchMessage<Image>::kKey}) {
    const bool imu = std::string(key) == BenchMessage<Imu>::kKey;
    benchmark::RegisterBenchmark((std::string("publish_call/") + key).c_str(),
                                 [imu, bus](benchmark::State& s) {
                                   imu ? publishCallRow<Imu>(s, bus)
                                       : publishCallRow<Image>(s, bus);
                                 })
        ->Iterations(1)
        ->Unit(benchmark::kMillisecond);
  }
  for (Transport t : {Transport::kInProcess, Transport::kSharedMemory, Transport::kUdpLoopback}) {
    registerRows<Imu>(t, bus);
    registerRows<Image>(t, bus);
  }
  const std::string load_before = loadAverage();
  benchmark::AddCustomContext("fastdds", FASTRTPS_VERSION_STR);
  benchmark::AddCustomContext("domain_id", std::to_string(bus.domain_id));
  benchmark::AddCustomContext("udp_profile", bus.udp_profiles_file);
  benchmark::AddCustomContext("bare_participant", bus.bare_in_own_participant ? "own" : "shared");
  benchmark::AddCustomContext("loadavg_at_start", load_before);
  benchmark::RunSpecifiedBenchmarks();
  printTable(load_before, loadAverage());
  benchmark::Shutdown();
  return 0;
}
