#!/usr/bin/env node
// A talker written with @foxglove/rtps itself: the peer's own check, independent of mcvio.
//
// It publishes the interop topics and ros_discovery_info the way a ROS 2 node does and writes
// the messages it sends as JSON, so `peer.js` can be proven against a known-good sender before
// it is pointed at mcvio. @foxglove/rtps has no publisher API and cannot fragment samples, so
// this uses its Writer/Participant internals, and every sample (the image too) must fit the
// 1400 byte datagram its Message buffer holds.
//
// Usage: node js_talker.js --domain <id> --out <expected.json> [--tamper]
//   --tamper writes a JSON with one Imu field altered, to see the peer fail.
"use strict";

const fs = require("fs");
const { MessageWriter } = require("@foxglove/rosmsg2-serialization");
const rmwDdsCommon = require("./rmw_dds_common");
const msgsCommon = require("@foxglove/rosmsg-msgs-common");
const rtps = require("@foxglove/rtps");
const { UdpSocketNode, getNetworkInterfaces } = require("@foxglove/rtps/nodejs");
const { rosTopicToDds, rosTypeToDds } = require("@foxglove/ros2");
const { typeHash } = require("./rihs01");

const NODE_NAME = "interop_talker";

function now() {
  const ms = Date.now();
  return { sec: Math.floor(ms / 1000), nsec: (ms % 1000) * 1e6 };
}

function args() {
  const out = { tamper: false };
  const a = process.argv.slice(2);
  for (let i = 0; i < a.length; i++) {
    if (a[i] === "--domain") out.domainId = Number(a[++i]);
    else if (a[i] === "--out") out.path = a[++i];
    else if (a[i] === "--tamper") out.tamper = true;
    else throw new Error(`unknown argument ${a[i]}`);
  }
  if (!Number.isInteger(out.domainId) || out.path == undefined) {
    throw new Error("usage: node js_talker.js --domain <id> --out <expected.json> [--tamper]");
  }
  return out;
}

function definitionsFor(rosType) {
  const [pkg, , name] = rosType.split("/");
  const all = msgsCommon.ros2jazzy;
  const root = all[`${pkg}/${name}`];
  return [root, ...Object.values(all).filter((d) => d !== root)];
}

const stamp = { sec: 1700000123, nanosec: 456789012 };
const header = (frame) => ({ stamp, frame_id: frame });
const seq = (n, f) => Array.from({ length: n }, (_, i) => f(i));

const width = 32;
const height = 24;
const MESSAGES = [
  {
    name: "/interop/image",
    type: "sensor_msgs/msg/Image",
    qos: "sensor",
    message: {
      header: header("cam0"),
      height,
      width,
      encoding: "mono8",
      is_bigendian: 1,
      step: width,
      data: seq(width * height, (i) => (i * 7 + Math.floor(i / width) * 13) & 0xff),
    },
  },
  {
    name: "/interop/imu",
    type: "sensor_msgs/msg/Imu",
    qos: "sensor",
    message: {
      header: header("imu0"),
      orientation: { x: 0.1, y: -0.2, z: 0.3, w: 0.9273618495495704 },
      orientation_covariance: seq(9, (i) => 1e-3 * (i + 1)),
      angular_velocity: { x: 0.01, y: -0.02, z: 0.03 },
      angular_velocity_covariance: seq(9, (i) => 2e-4 * (i + 1)),
      linear_acceleration: { x: 0.5, y: -0.25, z: 9.80665 },
      linear_acceleration_covariance: seq(9, (i) => 3e-2 * (i + 1)),
    },
  },
  {
    name: "/interop/camera_info",
    type: "sensor_msgs/msg/CameraInfo",
    qos: "latched",
    message: {
      header: header("cam0"),
      height: 480,
      width: 752,
      distortion_model: "plumb_bob",
      d: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-5, 0.0],
      k: [458.654, 0, 367.215, 0, 457.296, 248.375, 0, 0, 1],
      r: [0.9999, 0.001, -0.002, -0.001, 0.9999, 0.003, 0.002, -0.003, 0.9999],
      p: [458.654, 0, 367.215, -50.1, 0, 457.296, 248.375, 0.2, 0, 0, 1, 0.003],
      binning_x: 2,
      binning_y: 3,
      roi: { x_offset: 4, y_offset: 5, height: 6, width: 7, do_rectify: true },
    },
  },
  {
    name: "/interop/odometry",
    type: "nav_msgs/msg/Odometry",
    qos: "default",
    message: {
      header: header("world"),
      child_frame_id: "body",
      pose: {
        pose: { position: { x: 1.5, y: -2.25, z: 0.125 }, orientation: { x: 0, y: 0, z: 0.38268343236508978, w: 0.92387953251128674 } },
        covariance: seq(36, (i) => (i + 1) / 64),
      },
      twist: {
        twist: { linear: { x: 0.3, y: 0.2, z: -0.1 }, angular: { x: 0.01, y: 0.02, z: 0.03 } },
        covariance: seq(36, (i) => (36 - i) / 128),
      },
    },
  },
  {
    name: "/tf",
    type: "tf2_msgs/msg/TFMessage",
    qos: "default",
    message: {
      transforms: [
        {
          header: header("world"),
          child_frame_id: "body",
          transform: { translation: { x: 1, y: 2, z: 3 }, rotation: { x: 0, y: 0, z: 0, w: 1 } },
        },
        {
          header: header("body"),
          child_frame_id: "cam0",
          transform: {
            translation: { x: -0.0216, y: -0.0647, z: 0.0098 },
            rotation: { x: 0.5, y: -0.5, z: 0.5, w: -0.5 },
          },
        },
      ],
    },
  },
];

const QOS = {
  sensor: { reliability: rtps.Reliability.BestEffort, durability: rtps.Durability.Volatile, depth: 5 },
  default: { reliability: rtps.Reliability.Reliable, durability: rtps.Durability.Volatile, depth: 10 },
  latched: { reliability: rtps.Reliability.Reliable, durability: rtps.Durability.TransientLocal, depth: 1 },
};

async function main() {
  const opts = args();
  const participant = new rtps.Participant({
    name: NODE_NAME,
    addresses: [rtps.selectIPv4(getNetworkInterfaces())],
    domainId: opts.domainId,
    udpSocketCreate: UdpSocketNode.Create,
  });
  const prefix = participant.attributes.guidPrefix;
  const pubWriter = participant._writers.get(rtps.EntityIdBuiltin.PublicationsWriter);
  const userWriters = [];
  let nextId = 0x100;

  const addWriter = (topicName, typeName, qos, hash) => {
    const entityId = rtps.makeEntityId(nextId++, rtps.EntityKind.AppdefWriterNoKey);
    const attributes = {
      guidPrefix: prefix,
      entityId,
      topicName,
      typeName,
      durability: qos.durability,
      reliability: { kind: qos.reliability, maxBlockingTime: { sec: 0, nsec: 100000000 } },
      // Depth 1: this writer resends its whole history to readers that never acknowledge.
      history: { kind: rtps.HistoryKind.KeepLast, depth: 1 },
      protocolVersion: participant.attributes.protocolVersion,
      vendorId: participant.attributes.vendorId,
    };
    const writer = new rtps.Writer(attributes);
    participant._writers.set(entityId, writer);
    userWriters.push(writer);

    const guid = rtps.makeGuid(prefix, entityId);
    const params = new rtps.Parameters();
    params.topicName(topicName);
    params.typeName(typeName);
    params.durability(attributes.durability);
    params.reliability(attributes.reliability);
    params.history({ kind: rtps.HistoryKind.KeepLast, depth: qos.depth });
    params.protocolVersion(attributes.protocolVersion);
    params.vendorId(attributes.vendorId);
    params.endpointGuid(guid);
    params.userDataString(`typehash=${hash};`);
    params.finish();
    pubWriter.history.set({
      timestamp: now(),
      kind: rtps.ChangeKind.Alive,
      writerGuid: rtps.makeGuid(prefix, rtps.EntityIdBuiltin.PublicationsWriter),
      sequenceNumber: pubWriter.history.nextSequenceNum(),
      data: params.data,
      instanceHandle: guid,
    });
    return writer;
  };

  const write = (writer, data) => {
    const guid = rtps.makeGuid(prefix, writer.attributes.entityId);
    writer.history.set({
      timestamp: now(),
      kind: rtps.ChangeKind.Alive,
      writerGuid: guid,
      sequenceNumber: writer.history.nextSequenceNum(),
      data,
      instanceHandle: guid,
    });
  };

  const topics = MESSAGES.map((m) => {
    const writer = addWriter(rosTopicToDds(m.name), rosTypeToDds(m.type), QOS[m.qos],
      typeHash(m.type, msgsCommon.ros2jazzy));
    const payload = new MessageWriter(definitionsFor(m.type)).writeMessage(m.message);
    return { ...m, writer, payload };
  });

  const discoveryWriter = addWriter(
    "ros_discovery_info",
    rmwDdsCommon.DDS_TYPE,
    QOS.latched,
    typeHash(rmwDdsCommon.ROS_TYPE, rmwDdsCommon.rmwDdsCommonLookup()),
  );
  const gidOf = (entityId) => ({ data: Buffer.from(rtps.makeGuid(prefix, entityId), "hex") });
  const info = {
    gid: gidOf(rtps.EntityIdBuiltin.Participant),
    node_entities_info_seq: [
      {
        node_namespace: "/",
        node_name: NODE_NAME,
        reader_gid_seq: [],
        writer_gid_seq: topics.map((t) => gidOf(t.writer.attributes.entityId)),
      },
    ],
  };
  const infoDefs = rmwDdsCommon.participantEntitiesInfoDefinitions();
  write(discoveryWriter, new MessageWriter(infoDefs).writeMessage(info));

  // Remote readers are matched to our writers by hand: @foxglove/rtps only matches its readers.
  participant.on("discoveredSubscription", (reader) => {
    const remote = participant._participants.get(reader.guidPrefix);
    for (const writer of [...userWriters]) {
      const a = writer.attributes;
      if (a.topicName !== reader.topicName || a.typeName !== reader.typeName) continue;
      const ids = remote.localWriterIdToRemoteReaderIds.get(a.entityId) ?? [];
      if (!ids.includes(reader.entityId)) {
        ids.push(reader.entityId);
        remote.localWriterIdToRemoteReaderIds.set(a.entityId, ids);
      }
      void participant.sendDefaultChanges(writer);
    }
  });

  const expected = {
    node_namespace: "/",
    node_name: NODE_NAME,
    participant_gid: rtps.makeGuid(prefix, rtps.EntityIdBuiltin.Participant),
    topics: topics.map((t) => ({ name: t.name, type: t.type, message: t.message })),
  };
  if (opts.tamper) {
    expected.topics[1].message.linear_acceleration.z = 9.81;
  }
  fs.writeFileSync(opts.path, JSON.stringify(expected, null, 1));

  await participant.start();
  await participant.sendMetatrafficChanges(pubWriter);
  setInterval(() => {
    void participant.broadcastParticipant(participant.attributes);
    for (const t of topics) {
      write(t.writer, t.payload);
      void participant.sendDefaultChanges(t.writer);
    }
  }, 100);
  const stop = () => void participant.shutdown().then(() => process.exit(0));
  process.on("SIGTERM", stop);
  process.on("SIGINT", stop);
}

main().catch((err) => {
  console.error(`[js_talker] ${err.stack ?? err}`);
  process.exit(1);
});
