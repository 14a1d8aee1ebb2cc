#include "mcvio/dds/raw_payload_type.hpp"

#include <cstring>

namespace mcvio::dds {

RawPayloadType::RawPayloadType(const std::string& dds_type_name) {
  setName(dds_type_name.c_str());
  // Initial pool size only: payloads larger than this are reallocated (see fastdds_qos.cpp).
  m_typeSize = 64 * 1024;
  m_isGetKeyDefined = false;
}

bool RawPayloadType::serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) {
  const auto& bytes = *static_cast<RawPayload*>(data);
  if (bytes.size() < 4) return false;
  if (payload->max_size < bytes.size()) payload->reserve(static_cast<uint32_t>(bytes.size()));
  std::memcpy(payload->data, bytes.data(), bytes.size());
  payload->length = static_cast<uint32_t>(bytes.size());
  // The first two bytes are the encapsulation id (e.g. CDR_LE) that readers check.
  payload->encapsulation = static_cast<uint16_t>(bytes[1] == 0x01 ? CDR_LE : CDR_BE);
  return true;
}

bool RawPayloadType::deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) {
  auto& bytes = *static_cast<RawPayload*>(data);
  bytes.assign(payload->data, payload->data + payload->length);
  return true;
}

std::function<uint32_t()> RawPayloadType::getSerializedSizeProvider(void* data) {
  return [data]() { return static_cast<uint32_t>(static_cast<RawPayload*>(data)->size()); };
}

void* RawPayloadType::createData() { return new RawPayload(); }

void RawPayloadType::deleteData(void* data) { delete static_cast<RawPayload*>(data); }

bool RawPayloadType::getKey(void*, eprosima::fastrtps::rtps::InstanceHandle_t*, bool) { return false; }

}  // namespace mcvio::dds
