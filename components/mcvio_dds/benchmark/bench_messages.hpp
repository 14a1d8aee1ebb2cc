#pragma once
#include <chrono>
#include <cstddef>
#include <cstdint>

#include "mcvio/interfaces/ros_type_traits.hpp"

namespace mcvio::dds::bench {

using Image = sensor_msgs::msg::dds_::Image_;
using Imu = sensor_msgs::msg::dds_::Imu_;

/// The message each row sends and the most each row measures; the time budgets in dds_benchmark.cpp
/// usually stop a row first and keep the whole binary near a minute on two shared cores.
template <class T>
struct BenchMessage;

template <>
struct BenchMessage<Image> {
  static constexpr const char* kKey = "image";
  static constexpr const char* kLabel = "Image 752x480 mono8";
  static constexpr int kMaxPings = 4000;  ///< per API
  static constexpr int kBurst = 60;       ///< messages per throughput burst (22 MB)
  static constexpr int kMaxBurstPairs = 200;
  static Image make() {
    Image img;
    img.header().stamp().sec(1403715273);
    img.header().frame_id("cam0");
    img.height(480);
    img.width(752);
    img.encoding("mono8");
    img.step(752);
    img.data().resize(752 * 480);
    for (std::size_t i = 0; i < img.data().size(); ++i)
      img.data()[i] = static_cast<std::uint8_t>(i * 31u);
    return img;
  }
};

template <>
struct BenchMessage<Imu> {
  static constexpr const char* kKey = "imu";
  static constexpr const char* kLabel = "Imu";
  static constexpr int kMaxPings = 20000;
  static constexpr int kBurst = 500;
  static constexpr int kMaxBurstPairs = 200;
  static Imu make() {
    Imu imu;
    imu.header().stamp().sec(1403715273);
    imu.header().frame_id("imu0");
    imu.orientation().w(1.0);
    imu.angular_velocity().x(-0.0991);
    imu.angular_velocity().y(0.1326);
    imu.angular_velocity().z(0.0258);
    imu.linear_acceleration().x(8.1476);
    imu.linear_acceleration().y(-0.3718);
    imu.linear_acceleration().z(-3.8131);
    return imu;
  }
};

/// CDR size of `msg` on the wire, encapsulation header included: the payload MB/s counts.
template <class T>
std::size_t serializedSize(const T& msg) {
  typename interfaces::RosType<T>::PubSubType type;
  return type.getSerializedSizeProvider(const_cast<T*>(&msg))();
}

}  // namespace mcvio::dds::bench
