// libFuzzer target: the dynamic CDR decoder on arbitrary bytes must either decode or throw
// mcvio::InputError, never crash or allocate without bound; whatever it decodes must encode to a
// canonical payload that decodes and re-encodes to the same bytes.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "mcvio/core/input_error.hpp"
#include "mcvio/rosmsg/cdr_codec.hpp"

namespace {

const char* kDefinitions[][2] = {
    {"sensor_msgs/msg/Image",
     "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 step\n"
     "uint8[] data\n================================================================================\n"
     "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n"
     "================================================================================\n"
     "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n"},
    {"test_msgs/msg/Mixed",
     "bool flag\nint8 a\nint16 b\nfloat32 c\nfloat64[3] d\nstring<=8 s\nwstring w\nint64[<=4] e\n"
     "Point[] points\nstring[] names\n"
     "================================================================================\n"
     "MSG: test_msgs/Point\nfloat64 x\nfloat64 y\nuint16 id\n"},
    {"rmw_dds_common/msg/ParticipantEntitiesInfo",
     "Gid gid\nNodeEntitiesInfo[] node_entities_info_seq\n"
     "================================================================================\n"
     "MSG: rmw_dds_common/Gid\nuint8[16] data\n"
     "================================================================================\n"
     "MSG: rmw_dds_common/NodeEntitiesInfo\nstring<=256 node_namespace\nstring<=256 node_name\n"
     "Gid[] reader_gid_seq\nGid[] writer_gid_seq\n"},
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const auto sets = [] {
    std::vector<mcvio::rosmsg::MessageDefinitionSet> v;
    for (const auto& d : kDefinitions) v.push_back(mcvio::rosmsg::MessageDefinitionSet::parse(d[0], d[1]));
    return v;
  }();
  const auto& defs = sets[data[0] % sets.size()];
  mcvio::rosmsg::CdrCodec codec(defs);
  mcvio::rosmsg::MessageValue value;
  try {
    value = codec.decode(data + 1, size - 1);
  } catch (const mcvio::InputError&) {
    return 0;
  }
  // Compare canonical bytes, not values: NaN != NaN would flag a correct round trip.
  const auto canonical = codec.encode(value);
  if (codec.encode(codec.decode(canonical)) != canonical) std::abort();
  return 0;
}
