// ROS 2 type hash (RIHS01, REP-2011) computed from @foxglove message definitions, so the peer
// can check the `typehash=` user_data of a writer without trusting the sender's own computation.
//
// The hash is SHA-256 over the JSON of the type description (the type's fields and all types it
// references, sorted by name, without default values), printed with ", " and ": " separators.
"use strict";

const crypto = require("crypto");

// type_description_interfaces/msg/FieldType ids.
const TYPE_IDS = {
  nested: 1,
  int8: 2,
  uint8: 3,
  int16: 4,
  uint16: 5,
  int32: 6,
  uint32: 7,
  int64: 8,
  uint64: 9,
  float32: 10,
  float64: 11,
  char: 13,
  wchar: 14,
  bool: 15,
  byte: 16,
  string: 17,
  wstring: 18,
  boundedString: 21,
  boundedWstring: 22,
};
const ARRAY_OFFSET = 48;
const BOUNDED_SEQUENCE_OFFSET = 96;
const UNBOUNDED_SEQUENCE_OFFSET = 144;

// "sensor_msgs/Image" (foxglove naming) -> "sensor_msgs/msg/Image".
function rosTypeName(name) {
  const parts = name.split("/");
  return parts.length === 2 ? `${parts[0]}/msg/${parts[1]}` : name;
}

function foxgloveName(rosType) {
  const parts = rosType.split("/");
  return parts.length === 3 ? `${parts[0]}/${parts[2]}` : rosType;
}

function fieldType(field) {
  let base;
  let nested = "";
  let stringCapacity = 0;
  if (field.type === "time" || field.type === "duration") {
    base = TYPE_IDS.nested;
    nested = field.type === "time" ? "builtin_interfaces/msg/Time" : "builtin_interfaces/msg/Duration";
  } else if (field.isComplex === true) {
    base = TYPE_IDS.nested;
    nested = rosTypeName(field.type);
  } else if (field.type === "string" || field.type === "wstring") {
    const wide = field.type === "wstring";
    if (field.upperBound != undefined) {
      base = wide ? TYPE_IDS.boundedWstring : TYPE_IDS.boundedString;
      stringCapacity = field.upperBound;
    } else {
      base = wide ? TYPE_IDS.wstring : TYPE_IDS.string;
    }
  } else {
    base = TYPE_IDS[field.type];
    if (base == undefined) {
      throw new Error(`no RIHS01 type id for field ${field.name} of type ${field.type}`);
    }
  }
  let typeId = base;
  let capacity = 0;
  if (field.isArray === true) {
    if (field.arrayLength != undefined) {
      typeId += ARRAY_OFFSET;
      capacity = field.arrayLength;
    } else if (field.arrayUpperBound != undefined) {
      typeId += BOUNDED_SEQUENCE_OFFSET;
      capacity = field.arrayUpperBound;
    } else {
      typeId += UNBOUNDED_SEQUENCE_OFFSET;
    }
  }
  return { type_id: typeId, capacity, string_capacity: stringCapacity, nested_type_name: nested };
}

const BUILTIN_DEFINITIONS = {
  "builtin_interfaces/msg/Time": [
    { name: "sec", type: "int32" },
    { name: "nanosec", type: "uint32" },
  ],
  "builtin_interfaces/msg/Duration": [
    { name: "sec", type: "int32" },
    { name: "nanosec", type: "uint32" },
  ],
};

function individualDescription(rosType, definitions) {
  const fields = definitions.filter((f) => f.isConstant !== true);
  if (fields.length === 0) {
    fields.push({ name: "structure_needs_at_least_one_member", type: "uint8" });
  }
  return {
    type_name: rosType,
    fields: fields.map((f) => ({ name: f.name, type: fieldType(f) })),
  };
}

/**
 * RIHS01 hash of a ROS 2 message type.
 * @param rosType "pkg/msg/Name"
 * @param lookup map from foxglove names ("pkg/Name") to MessageDefinition
 */
function typeHash(rosType, lookup) {
  const definitionOf = (name) => {
    if (BUILTIN_DEFINITIONS[name] != undefined) return BUILTIN_DEFINITIONS[name];
    const def = lookup[foxgloveName(name)];
    if (def == undefined) throw new Error(`no definition of ${name} to hash`);
    return def.definitions;
  };
  const root = individualDescription(rosType, definitionOf(rosType));
  const referenced = new Map();
  const pending = root.fields.map((f) => f.type.nested_type_name).filter((n) => n !== "");
  while (pending.length > 0) {
    const name = pending.pop();
    if (referenced.has(name)) continue;
    const desc = individualDescription(name, definitionOf(name));
    referenced.set(name, desc);
    for (const f of desc.fields) {
      if (f.type.nested_type_name !== "") pending.push(f.type.nested_type_name);
    }
  }
  const description = {
    type_description: root,
    referenced_type_descriptions: [...referenced.keys()].sort().map((k) => referenced.get(k)),
  };
  // Python's json.dumps(separators=(", ", ": ")): a space after every comma and colon.
  const text = JSON.stringify(description).replace(/("(?:[^"\\]|\\.)*")|([,:])/g, (m, str, sep) =>
    str != undefined ? str : `${sep} `,
  );
  return `RIHS01_${crypto.createHash("sha256").update(text, "utf8").digest("hex")}`;
}

module.exports = { typeHash };
