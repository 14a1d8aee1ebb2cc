// Decoding and field-by-field comparison of ROS 2 messages against the talker's JSON.
"use strict";

const msgsCommon = require("@foxglove/rosmsg-msgs-common");

// ROS 2 type "pkg/msg/Name" -> the definition list MessageReader wants (root first).
function definitionsFor(rosType) {
  const [pkg, kind, name] = rosType.split("/");
  if (kind !== "msg" || name == undefined) {
    throw new Error(`unsupported ROS 2 type "${rosType}"`);
  }
  const all = msgsCommon.ros2jazzy;
  const root = all[`${pkg}/${name}`];
  if (root == undefined) {
    throw new Error(`@foxglove/rosmsg-msgs-common (ros2jazzy) has no definition of ${rosType}`);
  }
  return [root, ...Object.values(all).filter((def) => def !== root)];
}

function describe(value) {
  if (typeof value === "bigint") {
    return `${value}n`;
  }
  if (ArrayBuffer.isView(value)) {
    return `${value.constructor.name}(${value.length})`;
  }
  if (Array.isArray(value)) {
    return `array(${value.length})`;
  }
  return JSON.stringify(value);
}

// Field-by-field comparison of a decoded message with the talker's JSON. Numbers must be equal
// exactly: the talker prints doubles with 17 significant digits, which round-trips.
function compareFields(expected, actual, path, diffs) {
  const MAX_DIFFS = 20;
  const add = (text) => {
    if (diffs.length < MAX_DIFFS) {
      diffs.push(text);
    } else if (diffs.length === MAX_DIFFS) {
      diffs.push("... (more differences not shown)");
    }
  };
  if (Array.isArray(expected)) {
    if (!Array.isArray(actual) && !ArrayBuffer.isView(actual)) {
      add(`${path}: expected an array of ${expected.length}, got ${describe(actual)}`);
      return;
    }
    if (expected.length !== actual.length) {
      add(`${path}: expected ${expected.length} elements, got ${actual.length}`);
      return;
    }
    let mismatches = 0;
    for (let i = 0; i < expected.length; i++) {
      const local = [];
      compareFields(expected[i], actual[i], `${path}[${i}]`, local);
      if (local.length > 0) {
        mismatches++;
        local.forEach(add);
      }
    }
    if (mismatches > 1) {
      add(`${path}: ${mismatches} of ${expected.length} elements differ`);
    }
    return;
  }
  if (expected !== null && typeof expected === "object") {
    if (actual === null || typeof actual !== "object" || Array.isArray(actual)) {
      add(`${path}: expected a message, got ${describe(actual)}`);
      return;
    }
    for (const key of Object.keys(expected)) {
      if (!(key in actual)) {
        add(`${path}.${key}: in the expected JSON but not in the decoded message`);
      } else {
        compareFields(expected[key], actual[key], `${path}.${key}`, diffs);
      }
    }
    for (const key of Object.keys(actual)) {
      if (!(key in expected)) {
        add(`${path}.${key}: decoded as ${describe(actual[key])} but missing from the expected JSON`);
      }
    }
    return;
  }
  if (typeof expected === "number" && typeof actual === "bigint") {
    if (!Number.isSafeInteger(expected) || BigInt(expected) !== actual) {
      add(`${path}: expected ${describe(expected)}, got ${describe(actual)}`);
    }
    return;
  }
  if (typeof expected !== typeof actual || !Object.is(expected, actual)) {
    add(`${path}: expected ${describe(expected)}, got ${describe(actual)}`);
  }
}

// CDR payload checks that MessageReader does not make: plain CDR little endian, and no bytes
// left over beyond the alignment padding the encapsulation options announce (leftover bytes mean
// the sender's layout has fields the ROS 2 definition does not).
function checkEncapsulation(payload, reader) {
  const problems = [];
  if (payload.length < 4) {
    return [`payload of ${payload.length} bytes has no encapsulation header`];
  }
  const kind = (payload[0] << 8) | payload[1];
  if (kind !== 0x0001) {
    problems.push(`encapsulation 0x${kind.toString(16).padStart(4, "0")}, expected 0x0001 CDR_LE`);
  }
  const padding = payload[3] & 0x03;
  const leftover = payload.length - reader.lastReadByteLength();
  if (leftover > padding && leftover >= 4) {
    problems.push(
      `${leftover} bytes left after decoding ${reader.lastReadByteLength()} of ${payload.length}`,
    );
  }
  return problems;
}

module.exports = { definitionsFor, compareFields, checkEncapsulation };
