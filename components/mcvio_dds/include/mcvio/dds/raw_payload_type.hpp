#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <fastdds/dds/topic/TopicDataType.hpp>

namespace mcvio::dds {

/// A TopicDataType that moves the serialized CDR payload (with its 4-byte encapsulation header)
/// as bytes, under any type name. The recorder receives types it has never seen this way, and
/// bag playback republishes them unchanged.
class RawPayloadType : public eprosima::fastdds::dds::TopicDataType {
 public:
  explicit RawPayloadType(const std::string& dds_type_name);

  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override;
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override;
  std::function<uint32_t()> getSerializedSizeProvider(void* data) override;
  void* createData() override;
  void deleteData(void* data) override;
  bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle, bool force_md5) override;
};

/// What RawPayloadType carries: the payload bytes exactly as on the wire.
using RawPayload = std::vector<std::uint8_t>;

}  // namespace mcvio::dds
