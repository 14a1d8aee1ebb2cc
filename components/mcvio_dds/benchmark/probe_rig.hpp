#pragma once
#include <memory>

#include "bare_ping_pong.hpp"
#include "bench_messages.hpp"
#include "bench_topics.hpp"
#include "bench_transport.hpp"
#include "echo_process.hpp"
#include "wrapper_ping_pong.hpp"

namespace mcvio::dds::bench {

/// The measuring side of one benchmark row: a wrapper prober on an mcvio::dds::Participant and a
/// bare prober (on that participant's DomainParticipant or on one of its own, see BusConfig), both
/// alive at once so their runs can be interleaved. The echo ends live in the same participants
/// (in-process) or in an EchoProcess child (SHM, UDP).
template <class T>
class ProbeRig {
 public:
  ProbeRig(Transport transport, const BusConfig& bus) {
    const std::string key = BenchMessage<T>::kKey;
    if (transport != Transport::kInProcess)
      echo_process_ = std::make_unique<EchoProcess>(key, transport, bus);
    participant_ =
        Participant::create(wrapperParticipantOptions(bus, transport, "dds_bench_probe"));
    probe_node_ = participant_->createNode("dds_bench_probe");
    bare_participant_ = makeBareParticipant(bus, transport, *participant_, "dds_bench_bare_probe");
    if (transport == Transport::kInProcess) {
      // Same participant: a second node, as two composed components would be.
      echo_node_ = participant_->createNode("dds_bench_echo");
      wrapper_echo_ = std::make_unique<WrapperEchoer<T>>(*echo_node_, wrapperTopic(key, "ping"),
                                                         wrapperTopic(key, "pong"));
      bare_echo_ = std::make_unique<BareEchoer<T>>(*bare_participant_, bareTopic(key, "ping"),
                                                   bareTopic(key, "pong"));
    }
    wrapper_ = std::make_unique<WrapperProber<T>>(*probe_node_, wrapperTopic(key, "ping"),
                                                  wrapperTopic(key, "pong"));
    bare_ = std::make_unique<BareProber<T>>(*bare_participant_, bareTopic(key, "ping"),
                                            bareTopic(key, "pong"));
  }

  /// 0: wrapper, 1: bare.
  Prober<T>& prober(int api) { return api == 0 ? static_cast<Prober<T>&>(*wrapper_) : *bare_; }
  /// True when the echo child has died (only for SHM and UDP rows).
  bool echoProcessExited() { return echo_process_ && echo_process_->exited(); }

 private:
  // Declaration order is teardown order reversed: probers and echoes go before their participants,
  // the echo child is told to leave last.
  std::unique_ptr<EchoProcess> echo_process_;
  std::shared_ptr<Participant> participant_;
  std::shared_ptr<Node> probe_node_, echo_node_;
  std::unique_ptr<BareParticipant> bare_participant_;
  std::unique_ptr<Echoer> wrapper_echo_, bare_echo_;
  std::unique_ptr<WrapperProber<T>> wrapper_;
  std::unique_ptr<BareProber<T>> bare_;
};

}  // namespace mcvio::dds::bench
