#!/usr/bin/env node
// Independent ROS 2 peer for the mcvio interop test.
//
// It speaks RTPS through @foxglove/rtps (no Fast DDS, no ROS 2 install), discovers the DDS
// participants on a domain, maps their writers back to ROS 2 names and types the way ROS 2 tools
// do, subscribes to the expected topics, decodes every sample with the ROS 2 Jazzy message
// definitions from @foxglove/rosmsg-msgs-common and compares every field with the JSON the talker
// wrote. It also reads ros_discovery_info to find the talker's ROS 2 node.
//
// Usage: node peer.js --domain <id> --expected <talker.json> [--timeout <s>] [--address <ipv4>]
//                     [--verbose]
//        node peer.js --domain <id> --list [--timeout <s>]
//          (print the writers, readers and ros_discovery_info nodes seen within the timeout; exit 0)
// Exit status: 0 when everything matched, 1 on any mismatch or timeout, 2 on bad usage.
"use strict";

const fs = require("fs");
const { MessageReader } = require("@foxglove/rosmsg2-serialization");
const msgsCommon = require("@foxglove/rosmsg-msgs-common");
const rtps = require("@foxglove/rtps");
const { UdpSocketNode, getNetworkInterfaces } = require("@foxglove/rtps/nodejs");
const { ddsToRosTopic, ddsToRosType, rosTopicToDds, rosTypeToDds } = require("@foxglove/ros2");
const { typeHash } = require("./rihs01");
const rmwDdsCommon = require("./rmw_dds_common");
const { definitionsFor, compareFields, checkEncapsulation } = require("./message_check");

const DISCOVERY_TOPIC = "ros_discovery_info";
const DISCOVERY_DDS_TYPE = rmwDdsCommon.DDS_TYPE;
// Large enough to hold a whole fragmented 752x480 image in flight; the kernel caps it at
// net.core.rmem_max.
const RECV_BUFFER_BYTES = 8 * 1024 * 1024;
// Participants per host reached by unicast announcements (Fast DDS numbers them from 0).
const UNICAST_PARTICIPANT_IDS = 4;

const RELIABILITY_NAMES = { 1: "best_effort", 2: "reliable" };
const DURABILITY_NAMES = { 0: "volatile", 1: "transient_local", 2: "transient", 3: "persistent" };

function usage(message) {
  if (message) {
    console.error(`peer: ${message}`);
  }
  console.error(
    "usage: node peer.js --domain <id> (--expected <talker.json> | --list) [--timeout <s>] " +
      "[--address <ipv4>] [--verbose]",
  );
  process.exit(2);
}

function parseArgs(argv) {
  const opts = { timeoutS: 60, verbose: false, list: false };
  for (let i = 0; i < argv.length; i++) {
    const arg = argv[i];
    const value = () => {
      if (i + 1 >= argv.length) {
        usage(`${arg} needs a value`);
      }
      return argv[++i];
    };
    switch (arg) {
      case "--domain":
        opts.domainId = Number(value());
        break;
      case "--expected":
        opts.expectedPath = value();
        break;
      case "--timeout":
        opts.timeoutS = Number(value());
        break;
      case "--address":
        opts.address = value();
        break;
      case "--verbose":
        opts.verbose = true;
        break;
      case "--list":
        opts.list = true;
        break;
      default:
        usage(`unknown argument ${arg}`);
    }
  }
  if (!Number.isInteger(opts.domainId) || opts.domainId < 0 || opts.domainId > 232) {
    usage("--domain must be an integer in [0, 232]");
  }
  if (!(opts.timeoutS > 0)) {
    usage("--timeout must be a positive number of seconds");
  }
  if (!opts.list && opts.expectedPath == undefined) {
    usage("--expected or --list is required");
  }
  return opts;
}

// The talker's JSON: {node_namespace, node_name, participant_gid?, topics: [{name, type, message}],
// subscriptions?: [{name, type}]}.
// participant_gid (hex of the 16-byte ROS 2 GID) pins the talker's participant when given.
function loadExpected(path) {
  let doc;
  try {
    doc = JSON.parse(fs.readFileSync(path, "utf8"));
  } catch (err) {
    throw new Error(`cannot read expected messages from ${path}: ${err.message}`);
  }
  if (typeof doc.node_name !== "string" || typeof doc.node_namespace !== "string") {
    throw new Error(`${path}: node_name and node_namespace must be strings`);
  }
  if (doc.participant_gid !== undefined && !/^[0-9a-f]{32}$/.test(doc.participant_gid)) {
    throw new Error(`${path}: participant_gid must be 32 lower-case hex digits`);
  }
  if (!Array.isArray(doc.topics) || doc.topics.length === 0) {
    throw new Error(`${path}: topics must be a non-empty array`);
  }
  for (const [i, x] of (doc.subscriptions ?? []).entries()) {
    if (typeof x.name !== "string" || typeof x.type !== "string") {
      throw new Error(`${path}: subscriptions[${i}] needs string name and string type`);
    }
  }
  for (const [i, t] of doc.topics.entries()) {
    if (typeof t.name !== "string" || typeof t.type !== "string" || typeof t.message !== "object") {
      throw new Error(`${path}: topics[${i}] needs string name, string type and object message`);
    }
  }
  return doc;
}

// The writer's user_data must carry the RIHS01 hash ROS 2 Iron+ computes for its type.
function checkTypeHash(writer, rosType, lookup) {
  const guid = rtps.makeGuid(writer.guidPrefix, writer.entityId);
  const userData = writer.userData ?? "";
  const match = /(?:^|;)typehash=(RIHS01_[0-9a-f]{64});/.exec(userData);
  if (match == undefined) {
    return `writer ${guid} user_data is "${userData}", expected typehash=RIHS01_<64 hex>;`;
  }
  const expectedHash = typeHash(rosType, lookup);
  if (match[1] !== expectedHash) {
    return `writer ${guid} announces ${match[1]} for ${rosType}, its RIHS01 hash is ${expectedHash}`;
  }
  return undefined;
}

function bytesToHex(bytes) {
  return Buffer.from(bytes.buffer, bytes.byteOffset, bytes.byteLength).toString("hex");
}

function isBuiltinEntity(entityId) {
  return (entityId & 0xc0) === 0xc0;
}

// Reliability and durability are what discovery announces and what matching checks; Fast DDS
// does not announce its history kind or depth.
function qosString(endpoint) {
  return (
    `${RELIABILITY_NAMES[endpoint.reliability.kind] ?? endpoint.reliability.kind}, ` +
    `${DURABILITY_NAMES[endpoint.durability] ?? endpoint.durability}`
  );
}

// @foxglove/rtps 1.6 sends reader replies (ACKNACK, NACK_FRAG) to the writer participant's
// metatraffic locator. Fast DDS only listens for a user writer's replies on its data (default
// unicast) locators, so reliable repair from a Fast DDS writer stalls. Route replies for user
// writers to the remote participant's default unicast locators; builtin writers keep metatraffic.
function routeReaderRepliesToDataLocators(participant) {
  const dataLocators = (guidPrefix, writerEntityId, fallback) => {
    if (isBuiltinEntity(writerEntityId)) {
      return fallback;
    }
    const remote = participant._participants.get(guidPrefix);
    const locators = remote?.attributes.defaultUnicastLocatorList ?? [];
    return locators.length > 0 ? locators : fallback;
  };
  const sendAckNackTo = participant.sendAckNackTo;
  const sendNackFragTo = participant.sendNackFragTo;
  if (typeof sendAckNackTo !== "function" || typeof sendNackFragTo !== "function") {
    throw new Error("@foxglove/rtps changed: Participant.sendAckNackTo/sendNackFragTo not found");
  }
  participant.sendAckNackTo = function (reader, guidPrefix, writerId, first, last, final, locs) {
    const to = dataLocators(guidPrefix, writerId, locs);
    return sendAckNackTo.call(this, reader, guidPrefix, writerId, first, last, final, to);
  };
  participant.sendNackFragTo = function (guidPrefix, lastFrag, readerId, writerId, seq, frags, locs) {
    const to = dataLocators(guidPrefix, writerId, locs);
    return sendNackFragTo.call(this, guidPrefix, lastFrag, readerId, writerId, seq, frags, to);
  };
}

async function main() {
  const opts = parseArgs(process.argv.slice(2));
  const expected = opts.list ? undefined : loadExpected(opts.expectedPath);
  const log = (text) => console.log(`[peer] ${text}`);

  // Per expected topic: its DDS names, a reader for its ROS 2 type, and what arrived.
  const topics = new Map();
  for (const t of expected?.topics ?? []) {
    topics.set(rosTopicToDds(t.name), {
      rosName: t.name,
      rosType: t.type,
      ddsType: rosTypeToDds(t.type),
      reader: new MessageReader(definitionsFor(t.type)),
      expected: t.message,
      writers: [],
      subscribed: false,
      samples: 0,
      result: undefined, // "ok" or a list of differences
    });
  }
  // Per expected subscription of the talker (a reader ROS 2 tools must see): its DDS names.
  const subscriptions = new Map();
  for (const x of expected?.subscriptions ?? []) {
    subscriptions.set(rosTopicToDds(x.name), {
      rosName: x.name, rosType: x.type, ddsType: rosTypeToDds(x.type), readers: [],
    });
  }
  const discoveryReader = new MessageReader(
    rmwDdsCommon.participantEntitiesInfoDefinitions(),
  );
  // Fail before any networking if a type cannot be hashed (e.g. missing from msgs-common).
  for (const t of [...topics.values(), ...subscriptions.values()]) typeHash(t.rosType, msgsCommon.ros2jazzy);
  const discovery = {
    subscribed: false, samples: 0, writers: [], latest: new Map(), nodeFound: undefined, nodeProblems: [],
  };
  const participantsSeen = new Map();
  // With the talker's participant GID known, anything else on the domain (another test that
  // drew the same random domain) is ignored instead of being compared against our JSON.
  const fromTalker = (guidPrefix) =>
    expected?.participant_gid == undefined ||
    rtps.makeGuid(guidPrefix, rtps.EntityIdBuiltin.Participant) === expected.participant_gid;
  const writersSeen = new Map();
  const failures = [];

  const address = opts.address ?? rtps.selectIPv4(getNetworkInterfaces());
  const participant = new rtps.Participant({
    name: "mcvio_interop_peer",
    addresses: [address],
    domainId: opts.domainId,
    udpSocketCreate: UdpSocketNode.Create,
    udpSocketOptions: { type: "udp4", reuseAddr: true, recvBufferSize: RECV_BUFFER_BYTES },
    log: opts.verbose
      ? {
          debug: () => {},
          info: (m) => console.log(`[rtps] ${m}`),
          warn: (m) => console.log(`[rtps] WARN ${m}`),
          error: (m) => console.log(`[rtps] ERROR ${m}`),
        }
      : undefined,
  });
  routeReaderRepliesToDataLocators(participant);
  participant.on("error", (err) => {
    if (opts.verbose) log(`rtps error: ${err.message}`);
  });

  participant.on("discoveredParticipant", (p) => {
    participantsSeen.set(p.guidPrefix, p);
    log(`participant ${p.guidPrefix} vendor 0x${p.vendorId.toString(16)} ` +
      `user_data "${p.userData ?? ""}"`);
  });

  const subscribeLike = (topicName, typeName, writer) => {
    // Participant.subscribe accepts any QoS; ask for exactly what the writer offers so a best
    // effort or volatile writer matches as it would with a ROS 2 subscriber of the same profile.
    participant.subscribe({
      topicName,
      typeName,
      reliability: { kind: writer.reliability.kind, maxBlockingTime: { sec: 0, nsec: 100000000 } },
      durability: writer.durability,
      history: {
        kind: rtps.HistoryKind.KeepLast,
        depth: Math.max(1, writer.history.kind === rtps.HistoryKind.KeepLast ? writer.history.depth : 1),
      },
    });
  };

  participant.on("discoveredPublication", (w) => {
    const guid = rtps.makeGuid(w.guidPrefix, w.entityId);
    const isNew = !writersSeen.has(guid);
    writersSeen.set(guid, w);
    if (!isNew || w.topicName == undefined) {
      return;
    }
    const rosTopic = ddsToRosTopic(w.topicName);
    const rosType = ddsToRosType(w.typeName);
    log(`writer ${guid}: DDS ${w.topicName} [${w.typeName}] -> ROS ` +
      `${rosTopic ? rosTopic.topic : "(not a ROS topic)"} [${rosType ?? "(not a ROS type)"}] ` +
      `qos(${qosString(w)}) user_data "${w.userData ?? ""}"`);

    if (!fromTalker(w.guidPrefix)) {
      log(`  (ignored: not the talker's participant ${expected.participant_gid})`);
      return;
    }
    if (w.topicName === DISCOVERY_TOPIC) {
      discovery.writers.push(w);
      if (w.typeName !== DISCOVERY_DDS_TYPE) {
        failures.push(`${DISCOVERY_TOPIC} writer ${guid} has type ${w.typeName}, ` +
          `expected ${DISCOVERY_DDS_TYPE}`);
      } else if (!discovery.subscribed) {
        discovery.subscribed = true;
        // ROS 2 nodes read the graph reliable + transient local, keep last 1 (rmw_dds_common).
        participant.subscribe({
          topicName: DISCOVERY_TOPIC,
          typeName: DISCOVERY_DDS_TYPE,
          reliability: { kind: rtps.Reliability.Reliable, maxBlockingTime: { sec: 0, nsec: 100000000 } },
          durability: rtps.Durability.TransientLocal,
          history: { kind: rtps.HistoryKind.KeepLast, depth: 1 },
        });
      }
      return;
    }
    const topic = topics.get(w.topicName);
    if (opts.list || topic == undefined) {
      return;
    }
    topic.writers.push(w);
    if (w.typeName !== topic.ddsType) {
      topic.result = [`writer ${guid} on ${w.topicName} has DDS type ${w.typeName}, ` +
        `a ROS 2 ${topic.rosType} subscriber needs ${topic.ddsType}`];
      return;
    }
    if (!topic.subscribed) {
      topic.subscribed = true;
      subscribeLike(w.topicName, w.typeName, w);
    }
  });

  participant.on("discoveredSubscription", (r) => {
    const guid = rtps.makeGuid(r.guidPrefix, r.entityId);
    if (r.topicName == undefined || r.topicName === DISCOVERY_TOPIC) return;
    const sub = subscriptions.get(r.topicName);
    if (opts.list || sub == undefined || !fromTalker(r.guidPrefix)) {
      if (opts.list) {
        log(`reader ${guid}: DDS ${r.topicName} [${r.typeName}] qos(${qosString(r)}) user_data "${r.userData ?? ""}"`);
      }
      return;
    }
    if (sub.readers.some((x) => rtps.makeGuid(x.guidPrefix, x.entityId) === guid)) return;
    sub.readers.push(r);
    log(`reader ${guid}: DDS ${r.topicName} [${r.typeName}] -> ROS ${sub.rosName} ` +
      `qos(${qosString(r)}) user_data "${r.userData ?? ""}"`);
    checkDone();
  });

  let finish;
  const done = new Promise((resolve) => (finish = resolve));
  const checkDone = () => {
    if (opts.list) return;
    evaluateDiscovery();
    const allTopics = [...topics.values()].every((t) => t.result !== undefined);
    const allReaders = [...subscriptions.values()].every((x) => x.readers.length > 0);
    if (allTopics && allReaders && discovery.nodeFound !== undefined) finish("complete");
  };

  participant.on("userData", (data) => {
    const topicName = data.subscription.topicName;
    const payload = data.serializedData;
    if (!fromTalker(data.publication.guidPrefix)) {
      return;
    }
    if (topicName === DISCOVERY_TOPIC) {
      discovery.samples++;
      let info;
      try {
        info = discoveryReader.readMessage(payload);
      } catch (err) {
        failures.push(`${DISCOVERY_TOPIC}: cannot decode a ${payload.length} byte sample as ` +
          `Jazzy ParticipantEntitiesInfo: ${err.message}`);
        finish("decode error");
        return;
      }
      const problems = checkEncapsulation(payload, discoveryReader);
      if (problems.length > 0) {
        failures.push(`${DISCOVERY_TOPIC}: ${problems.join("; ")}`);
      }
      describeDiscovery(info, data.publication.guidPrefix);
      discovery.latest.set(data.publication.guidPrefix, info);
      checkDone();
      return;
    }
    const topic = topics.get(topicName);
    if (topic == undefined || topic.result === "ok") {
      return;
    }
    topic.samples++;
    let msg;
    try {
      msg = topic.reader.readMessage(payload);
    } catch (err) {
      topic.result = [`cannot decode a ${payload.length} byte sample as ${topic.rosType}: ${err.message}`];
      checkDone();
      return;
    }
    const diffs = checkEncapsulation(payload, topic.reader);
    compareFields(topic.expected, msg, topic.rosName, diffs);
    topic.result = diffs.length === 0 ? "ok" : diffs;
    log(`${topic.rosName}: sample ${topic.samples} (${payload.length} bytes) ` +
      (diffs.length === 0 ? "matches the talker's JSON field by field" : `has ${diffs.length} difference(s)`));
    checkDone();
  });

  function describeDiscovery(info, senderPrefix) {
    const nodes = info.node_entities_info_seq.map((n) =>
      `${n.node_namespace === "/" ? "" : n.node_namespace}/${n.node_name} ` +
      `(${n.writer_gid_seq.length} writers, ${n.reader_gid_seq.length} readers)`);
    log(`${DISCOVERY_TOPIC} from ${senderPrefix}: gid ${bytesToHex(info.gid.data)}, nodes ` +
      (nodes.join(", ") || "(none)"));
  }

  // The talker's node must be listed by its participant, with the GIDs of the writers of every
  // expected topic and of the readers of every expected subscription: that is how
  // `ros2 node info` and rqt_graph tie endpoints to nodes. Evaluated over the latest sample of
  // each participant, since a sample may predate endpoints created after it.
  function evaluateDiscovery() {
    if (expected == undefined) return;
    const problems = [];
    let found;
    for (const [senderPrefix, info] of discovery.latest) {
      const node = info.node_entities_info_seq.find(
        (n) => n.node_name === expected.node_name && n.node_namespace === expected.node_namespace);
      if (node == undefined) continue;
      const participantGid = bytesToHex(info.gid.data);
      const senderGid = rtps.makeGuid(senderPrefix, rtps.EntityIdBuiltin.Participant);
      if (participantGid !== senderGid) {
        problems.push(`ParticipantEntitiesInfo.gid is ${participantGid}, the sending participant's ` +
          `GUID is ${senderGid}`);
      }
      const writerGids = new Set(node.writer_gid_seq.map((g) => bytesToHex(g.data)));
      const readerGids = new Set(node.reader_gid_seq.map((g) => bytesToHex(g.data)));
      const need = [
        ...[...topics.values()].map((t) => ({ what: t.rosName, endpoints: t.writers, gids: writerGids, seq: "writer_gid_seq" })),
        ...[...subscriptions.values()].map((x) => ({ what: x.rosName, endpoints: x.readers, gids: readerGids, seq: "reader_gid_seq" })),
      ];
      for (const { what, endpoints, gids, seq } of need) {
        const own = endpoints.filter((e) => e.guidPrefix === senderPrefix);
        if (own.length === 0) {
          problems.push(`no endpoint of ${what} from participant ${senderPrefix} discovered yet`);
        }
        for (const e of own) {
          const gid = rtps.makeGuid(e.guidPrefix, e.entityId);
          if (!gids.has(gid)) problems.push(`${gid} (${what}) is not in ${expected.node_name}'s ${seq}`);
        }
      }
      found = { namespace: node.node_namespace, name: node.node_name, writers: writerGids.size, readers: readerGids.size };
    }
    discovery.nodeProblems = problems;
    discovery.nodeFound = found !== undefined && problems.length === 0 ? found : undefined;
  }


  log(`domain ${opts.domainId}, advertising ${address}, timeout ${opts.timeoutS} s`);
  await participant.start();
  for (const socket of [participant.unicastSocket, participant.multicastSocket]) {
    const raw = socket?._socket;
    if (raw != undefined && opts.verbose) {
      log(`socket receive buffer ${raw.getRecvBufferSize()} bytes`);
    }
  }
  // Re-announce ourselves now and then: a participant that starts after us learns of us from
  // its own multicast announcement, but one whose first multicast packet we missed does not.
  // Besides multicast, announce to the well-known metatraffic unicast ports of the first
  // participants on this host (what Fast DDS's default initial peers do), so discovery also
  // works where multicast does not reach.
  const multicastLocator = participant._multicastLocator;
  const unicastTargets = [];
  for (const host of new Set(["127.0.0.1", address])) {
    for (let id = 0; id < UNICAST_PARTICIPANT_IDS; id++) {
      unicastTargets.push(rtps.locatorFromUdpAddress({
        address: host, family: "IPv4", port: rtps.discoveryUnicastPort(opts.domainId, id),
      }));
    }
  }
  const announce = async () => {
    await participant.broadcastParticipant(participant.attributes);
    // broadcastParticipant sends to _multicastLocator; point it at each unicast port in turn.
    for (const locator of unicastTargets) {
      participant._multicastLocator = locator;
      await participant.broadcastParticipant(participant.attributes).catch(() => {});
    }
    participant._multicastLocator = multicastLocator;
  };
  void announce();
  const announceTimer = setInterval(() => void announce(), 1000);

  const timer = setTimeout(() => finish("timeout"), opts.timeoutS * 1000);
  const outcome = await done;
  clearTimeout(timer);
  clearInterval(announceTimer);

  // Report.
  let ok = outcome === "complete" && failures.length === 0;
  if (opts.list) {
    await participant.shutdown();
    return 0;
  }
  console.log(`\n[peer] result (${outcome}):`);
  const talkerPrefixes = new Set([...topics.values()].flatMap((t) => t.writers.map((w) => w.guidPrefix)));
  if (talkerPrefixes.size === 0) {
    ok = false;
    console.log(`  FAIL no writer of any expected topic was discovered on domain ${opts.domainId} ` +
      `(${participantsSeen.size} participant(s) seen)`);
  }
  for (const prefix of talkerPrefixes) {
    const p = participantsSeen.get(prefix);
    const userData = p?.userData ?? "";
    if (!/(^|;)enclave=\/;/.test(userData)) {
      ok = false;
      console.log(`  FAIL participant ${prefix} user_data is "${userData}", ROS 2 expects "enclave=/;"`);
    } else {
      console.log(`  ok   participant ${prefix} user_data "${userData}"`);
    }
  }
  for (const t of topics.values()) {
    for (const w of t.writers) {
      const problem = checkTypeHash(w, t.rosType, msgsCommon.ros2jazzy);
      if (problem !== undefined) {
        ok = false;
        console.log(`  FAIL ${t.rosName}: ${problem}`);
      }
    }
    if (t.result === "ok") {
      const w = t.writers[0];
      console.log(`  ok   ${t.rosName} [${t.rosType}] qos(${qosString(w)}): all fields equal`);
    } else {
      ok = false;
      if (t.result === undefined) {
        const why = t.writers.length === 0
          ? `no writer on DDS topic ${rosTopicToDds(t.rosName)} discovered`
          : `writer discovered, no sample received`;
        console.log(`  FAIL ${t.rosName} [${t.rosType}]: ${why}`);
      } else {
        console.log(`  FAIL ${t.rosName} [${t.rosType}]:`);
        for (const d of t.result) console.log(`         ${d}`);
      }
    }
  }
  for (const w of discovery.writers.filter((x) => talkerPrefixes.has(x.guidPrefix))) {
    const problem = checkTypeHash(w, rmwDdsCommon.ROS_TYPE, rmwDdsCommon.rmwDdsCommonLookup());
    if (problem !== undefined) {
      ok = false;
      console.log(`  FAIL ${DISCOVERY_TOPIC}: ${problem}`);
    }
  }
  for (const x of subscriptions.values()) {
    if (x.readers.length === 0) {
      ok = false;
      console.log(`  FAIL subscription ${x.rosName} [${x.rosType}]: no reader on ${rosTopicToDds(x.rosName)} discovered`);
      continue;
    }
    for (const r of x.readers) {
      const problems = [];
      if (r.typeName !== x.ddsType) problems.push(`DDS type ${r.typeName}, expected ${x.ddsType}`);
      const hashProblem = checkTypeHash(r, x.rosType, msgsCommon.ros2jazzy);
      if (hashProblem !== undefined) problems.push(hashProblem);
      if (problems.length > 0) {
        ok = false;
        console.log(`  FAIL subscription ${x.rosName}: ${problems.join("; ")}`);
      } else {
        console.log(`  ok   subscription ${x.rosName} [${x.rosType}] qos(${qosString(r)}), type hash matches`);
      }
    }
  }
  evaluateDiscovery();
  if (discovery.nodeFound !== undefined) {
    const n = discovery.nodeFound;
    console.log(`  ok   ${DISCOVERY_TOPIC}: node ${n.namespace === "/" ? "" : n.namespace}/${n.name} ` +
      `lists ${n.writers} writer and ${n.readers} reader gid(s), covering every expected endpoint`);
  } else {
    ok = false;
    if (!discovery.subscribed) {
      console.log(`  FAIL ${DISCOVERY_TOPIC}: no writer discovered`);
    } else if (discovery.samples === 0) {
      console.log(`  FAIL ${DISCOVERY_TOPIC}: writer discovered, no sample received`);
    } else if (discovery.nodeProblems.length > 0) {
      console.log(`  FAIL ${DISCOVERY_TOPIC}: node ${expected.node_name} found but:`);
      for (const d of discovery.nodeProblems) console.log(`         ${d}`);
    } else {
      console.log(`  FAIL ${DISCOVERY_TOPIC}: no node ${expected.node_namespace} ${expected.node_name} ` +
        `in ${discovery.samples} sample(s)`);
    }
  }
  for (const f of failures) {
    console.log(`  FAIL ${f}`);
  }
  console.log(ok ? "[peer] PASS" : "[peer] FAIL");
  await participant.shutdown();
  return ok ? 0 : 1;
}

main().then(
  (code) => process.exit(code),
  (err) => {
    console.error(`[peer] error: ${err.stack ?? err}`);
    process.exit(1);
  },
);
