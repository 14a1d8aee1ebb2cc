#!/usr/bin/env node
// Checks rihs01.js against RIHS01 hashes that ROS 2's own generator (rosidl_generator_type_description)
// produced for the message packages, as found in generated rosidl C code. If these hold, the peer's
// typehash check of mcvio's writers compares against what a ROS 2 Jazzy node computes.
"use strict";

const msgsCommon = require("@foxglove/rosmsg-msgs-common");
const { typeHash } = require("./rihs01");
const { rmwDdsCommonLookup } = require("./rmw_dds_common");

const REFERENCE = [
  ["builtin_interfaces/msg/Time", "b106235e25a4c5ed35098aa0a61a3ee9c9b18d197f398b0e4206cea9acf9c197"],
  ["std_msgs/msg/String", "df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"],
  ["std_msgs/msg/Header", "f49fb3ae2cf070f793645ff749683ac6b06203e41c891e17701b1cb597ce6a01"],
  ["geometry_msgs/msg/Vector3", "cc12fe83e4c02719f1ce8070bfd14aecd40f75a96696a67a2a1f37f7dbb0765d"],
  ["geometry_msgs/msg/PoseWithCovariance", "9a7c0fd234b7f45c6098745ecccd773ca1085670e64107135397aee31c02e1bb"],
  ["sensor_msgs/msg/Image", "d31d41a9a4c4bc8eae9be757b0beed306564f7526c88ea6a4588fb9582527d47"],
  ["sensor_msgs/msg/Imu", "7d9a00ff131080897a5ec7e26e315954b8eae3353c3f995c55faf71574000b5b"],
  ["sensor_msgs/msg/CameraInfo", "b3dfd68ff46c9d56c80fd3bd4ed22c7a4ddce8c8348f2f59c299e73118e7e275"],
  ["sensor_msgs/msg/RegionOfInterest", "ad16bcba5f9131dcdba6fbded19f726f5440e3c513b4fb586dd3027eeed8abb1"],
  ["nav_msgs/msg/Odometry", "3cc97dc7fb7502f8714462c526d369e35b603cfc34d946e3f2eda2766dfec6e0"],
  ["tf2_msgs/msg/TFMessage", "e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087"],
  ["rmw_dds_common/msg/ParticipantEntitiesInfo", "91a0593bacdcc50ea9bdcf849a938b128412cc1ea821245c663bcd26f83c295e"],
];

let failed = 0;
for (const [rosType, hex] of REFERENCE) {
  const lookup = rosType.startsWith("rmw_dds_common/") ? rmwDdsCommonLookup() : msgsCommon.ros2jazzy;
  const got = typeHash(rosType, lookup);
  const ok = got === `RIHS01_${hex}`;
  failed += ok ? 0 : 1;
  console.log(`${ok ? "ok  " : "FAIL"} ${rosType} ${got}${ok ? "" : ` (ROS 2: RIHS01_${hex})`}`);
}
process.exit(failed === 0 ? 0 : 1);
