// rmw_dds_common/msg/ParticipantEntitiesInfo, the type of ros_discovery_info through which ROS 2
// nodes announce themselves. @foxglove/rosmsg-msgs-common does not ship rmw_dds_common; this is
// the Jazzy layout (Gid became a fixed uint8[16] in Iron). Its RIHS01 hash equals the one
// generated for ROS 2's own rmw_dds_common, which rihs01.test.js checks.
"use strict";

const { parse } = require("@foxglove/rosmsg");

const PARTICIPANT_ENTITIES_INFO_MSG = `
Gid gid
NodeEntitiesInfo[] node_entities_info_seq
================================================================================
MSG: rmw_dds_common/Gid
uint8[16] data
================================================================================
MSG: rmw_dds_common/NodeEntitiesInfo
string<=256 node_namespace
string<=256 node_name
Gid[] reader_gid_seq
Gid[] writer_gid_seq
`;

const ROS_TYPE = "rmw_dds_common/msg/ParticipantEntitiesInfo";
const DDS_TYPE = "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_";

/** Definitions for MessageReader/MessageWriter, root first. */
function participantEntitiesInfoDefinitions() {
  return parse(PARTICIPANT_ENTITIES_INFO_MSG, { ros2: true });
}

/** Definitions keyed by foxglove name ("rmw_dds_common/Gid"), as rihs01.typeHash wants them. */
function rmwDdsCommonLookup() {
  const defs = participantEntitiesInfoDefinitions();
  const lookup = { "rmw_dds_common/ParticipantEntitiesInfo": defs[0] };
  for (const def of defs.slice(1)) lookup[def.name] = def;
  return lookup;
}

module.exports = { ROS_TYPE, DDS_TYPE, participantEntitiesInfoDefinitions, rmwDdsCommonLookup };
