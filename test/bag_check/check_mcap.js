// Independent check of mcvio's MCAP output with Foxglove's readers: reads every bag written by
// bag_check_generator through the summary (McapIndexedReader) and linearly with CRC checks
// (McapStreamReader), decodes every payload with the embedded ros2msg definition and compares
// it with expected.json.   node check_mcap.js OUT_DIR
"use strict";
const fs = require("fs");
const path = require("path");
const assert = require("assert");
const { McapIndexedReader, McapStreamReader } = require("@mcap/core");
const { parse } = require("@foxglove/rosmsg");
const { MessageReader } = require("@foxglove/rosmsg2-serialization");
const fzstd = require("fzstd");
const lz4 = require("lz4js");

const decompressHandlers = {
  zstd: (buffer, size) => fzstd.decompress(buffer, new Uint8Array(Number(size))),
  lz4: (buffer, size) => Uint8Array.from(lz4.decompress(buffer, Number(size))),
};

function bufferReadable(buf) {
  return {
    size: async () => BigInt(buf.length),
    read: async (offset, length) => buf.subarray(Number(offset), Number(offset + length)),
  };
}

function checkTopics(channels, schemas, bag) {
  const topics = new Map();
  for (const ch of channels.values()) {
    const schema = schemas.get(ch.schemaId);
    assert.ok(schema, `${bag}: channel ${ch.topic} has no schema`);
    assert.strictEqual(schema.encoding, "ros2msg", `${bag}: schema encoding`);
    assert.strictEqual(ch.messageEncoding, "cdr", `${bag}: message encoding`);
    assert.ok(ch.metadata.get("offered_qos_profiles").includes("reliability: 1"), `${bag}: qos`);
    const text = new TextDecoder().decode(schema.data);
    const reader = new MessageReader(parse(text, { ros2: true }));
    topics.set(ch.id, { topic: ch.topic, type: schema.name, reader });
  }
  return topics;
}

// rosmsg2-serialization returns builtin_interfaces/Time as {sec, nsec} (Foxglove's Time type);
// the ROS 2 field is "nanosec", which is what expected.json names.
function toPlain(v) {
  return JSON.parse(JSON.stringify(v, (_k, x) => {
    if (typeof x === "bigint") return Number(x);
    if (x && typeof x === "object" && "sec" in x && "nsec" in x && !("nanosec" in x)) {
      return { sec: x.sec, nanosec: x.nsec };
    }
    return x;
  }));
}

async function checkBag(dir, expected) {
  const bag = path.basename(dir);
  const files = fs.readdirSync(dir).filter((f) => f.endsWith(".mcap"));
  assert.strictEqual(files.length, 1, `${bag}: one mcap file`);
  const meta = fs.readFileSync(path.join(dir, "metadata.yaml"), "utf8");
  assert.ok(meta.includes("storage_identifier: mcap"), `${bag}: metadata.yaml storage`);
  const buf = new Uint8Array(fs.readFileSync(path.join(dir, files[0])));
  const want = expected.filter((m) => m.bag === bag);

  // 1. Indexed read through the summary.
  const indexed = await McapIndexedReader.Initialize({ readable: bufferReadable(buf), decompressHandlers });
  assert.strictEqual(indexed.header.profile, "ros2", `${bag}: profile`);
  assert.strictEqual(Number(indexed.statistics.messageCount), want.length, `${bag}: statistics`);
  assert.ok(indexed.chunkIndexes.length > 3, `${bag}: several chunks`);
  assert.ok(want.length > 0, `${bag}: expected messages`);
  const topics = checkTopics(indexed.channelsById, indexed.schemasById, bag);
  // rosbag2's MCAP plugin stores metadata.yaml in a Metadata record named "rosbag2".
  // (a repaired file lost it with the rest of its unfinished tail).
  let rosbag2Metadata = 0;
  for await (const m of indexed.readMetadata({ name: "rosbag2" })) {
    assert.ok(m.metadata.get("serialized_metadata").includes("rosbag2_bagfile_information:"), `${bag}: rosbag2 metadata`);
    rosbag2Metadata++;
  }
  assert.strictEqual(rosbag2Metadata, bag === "repaired" ? 0 : 1, `${bag}: rosbag2 Metadata records`);
  const got = [];
  for await (const msg of indexed.readMessages()) {
    const t = topics.get(msg.channelId);
    got.push({ topic: t.topic, log_time: msg.logTime.toString(), publish_time: msg.publishTime.toString(),
      value: toPlain(t.reader.readMessage(msg.data)) });
  }
  assert.strictEqual(got.length, want.length, `${bag}: message count (indexed)`);
  for (let i = 0; i < want.length; i++) {
    assert.deepStrictEqual(got[i], { topic: want[i].topic, log_time: want[i].log_time,
      publish_time: want[i].publish_time, value: want[i].value }, `${bag}: message ${i} (indexed)`);
  }

  // 2. Linear read of every record with CRC validation.
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true, includeChunks: false });
  stream.append(buf);
  const channels = new Map();
  const schemas = new Map();
  let n = 0;
  let sawFooter = false;
  for (let rec; (rec = stream.nextRecord()); ) {
    if (rec.type === "Schema") schemas.set(rec.id, rec);
    if (rec.type === "Channel") channels.set(rec.id, rec);
    if (rec.type === "Footer") sawFooter = true;
    if (rec.type === "Message") {
      const t = checkTopics(channels, schemas, bag).get(rec.channelId);
      assert.deepStrictEqual(toPlain(t.reader.readMessage(rec.data)), want[n].value, `${bag}: message ${n} (stream)`);
      n++;
    }
  }
  assert.ok(sawFooter && stream.done(), `${bag}: stream reader reached the footer`);
  assert.strictEqual(n, want.length, `${bag}: message count (stream)`);
  console.log(`${bag}: ${want.length} messages, ${indexed.chunkIndexes.length} chunks, ${topics.size} schemas OK`);
}

async function main() {
  const out = process.argv[2];
  const expected = JSON.parse(fs.readFileSync(path.join(out, "expected.json"), "utf8")).messages;
  for (const bag of ["none", "zstd", "lz4", "repaired"]) await checkBag(path.join(out, bag), expected);
  console.log(`node ${process.version}: all bags match`);
}

main().catch((e) => {
  console.error(e && e.stack ? e.stack : e);
  process.exit(1);
});
