#pragma once
#include <optional>
#include <string>
#include <string_view>

namespace mcvio::interfaces {

/// "sensor_msgs/msg/Image" -> "sensor_msgs::msg::dds_::Image_" (the name rmw_fastrtps registers).
/// Throws std::invalid_argument when `ros_type` is not of the form pkg/msg/Name.
std::string rosToDdsTypeName(std::string_view ros_type);

/// "sensor_msgs::msg::dds_::Image_" -> "sensor_msgs/msg/Image"; nullopt for a type name that does
/// not follow the ROS 2 convention (a plain DDS application's type).
std::optional<std::string> ddsToRosTypeName(std::string_view dds_type);

}  // namespace mcvio::interfaces
