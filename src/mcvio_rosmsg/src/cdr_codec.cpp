#include "mcvio/rosmsg/cdr_codec.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

#include "mcvio/core/input_error.hpp"

namespace mcvio::rosmsg {
namespace {

constexpr std::size_t kHeader = 4;  // encapsulation id (2) + options (2)
// A sequence longer than the bytes left cannot be real; checking this first keeps a corrupt
// length from allocating gigabytes.
constexpr std::size_t kMaxElements = 1u << 28;

class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size, bool little_endian)
      : data_(data), size_(size), little_(little_endian) {}

  void align(std::size_t n, const std::string& field) {
    const std::size_t rel = pos_ - kHeader;
    const std::size_t pad = (n - rel % n) % n;
    need(pad, field);
    pos_ += pad;
  }
  void need(std::size_t n, const std::string& field) const {
    if (n > size_ - pos_) {
      throw InputError("CDR payload truncated at byte " + std::to_string(pos_) + " while reading '" +
                       field + "' (needs " + std::to_string(n) + " more, has " +
                       std::to_string(size_ - pos_) + ")");
    }
  }
  template <class T>
  T read(const std::string& field) {
    align(sizeof(T), field);
    need(sizeof(T), field);
    T v;
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, data_ + pos_, sizeof(T));
    if (!little_) std::reverse(b, b + sizeof(T));
    std::memcpy(&v, b, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::uint32_t count(const std::string& field, std::size_t min_element_size) {
    const auto n = read<std::uint32_t>(field);
    if (n > kMaxElements || (min_element_size > 0 && n > (size_ - pos_) / min_element_size)) {
      throw InputError("CDR length " + std::to_string(n) + " of '" + field + "' at byte " +
                       std::to_string(pos_ - 4) + " exceeds the payload");
    }
    return n;
  }
  std::string readString(const std::string& field) {
    const auto n = count(field, 1);
    need(n, field);
    // The length includes the terminating NUL; tolerate writers that omit it.
    std::size_t len = n;
    if (len > 0 && data_[pos_ + len - 1] == 0) --len;
    std::string s(reinterpret_cast<const char*>(data_ + pos_), len);
    pos_ += n;
    return s;
  }
  std::vector<std::uint8_t> readBytes(std::size_t n, const std::string& field) {
    need(n, field);
    std::vector<std::uint8_t> b(data_ + pos_, data_ + pos_ + n);
    pos_ += n;
    return b;
  }
  std::size_t pos() const { return pos_; }
  void skipHeader() { pos_ = kHeader; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  bool little_;
};

bool isByteLike(FieldKind k) {
  return k == FieldKind::kByte || k == FieldKind::kUint8 || k == FieldKind::kChar;
}

MessageValue readPrimitive(Reader& r, FieldKind kind, const std::string& field) {
  MessageValue v;
  switch (kind) {
    case FieldKind::kBool: v.value = r.read<std::uint8_t>(field) != 0; break;
    case FieldKind::kByte: case FieldKind::kChar: case FieldKind::kUint8:
      v.value = std::uint64_t{r.read<std::uint8_t>(field)}; break;
    case FieldKind::kInt8: v.value = std::int64_t{r.read<std::int8_t>(field)}; break;
    case FieldKind::kInt16: v.value = std::int64_t{r.read<std::int16_t>(field)}; break;
    case FieldKind::kUint16: v.value = std::uint64_t{r.read<std::uint16_t>(field)}; break;
    case FieldKind::kInt32: v.value = std::int64_t{r.read<std::int32_t>(field)}; break;
    case FieldKind::kUint32: v.value = std::uint64_t{r.read<std::uint32_t>(field)}; break;
    case FieldKind::kInt64: v.value = std::int64_t{r.read<std::int64_t>(field)}; break;
    case FieldKind::kUint64: v.value = std::uint64_t{r.read<std::uint64_t>(field)}; break;
    case FieldKind::kFloat32: v.value = double{r.read<float>(field)}; break;
    case FieldKind::kFloat64: v.value = r.read<double>(field); break;
    case FieldKind::kString: v.value = r.readString(field); break;
    case FieldKind::kWString: {
      // wstring: length in 32-bit characters; shown as a narrowed string.
      const auto n = r.count(field, 4);
      std::string s;
      for (std::uint32_t i = 0; i < n; ++i) s += static_cast<char>(r.read<std::uint32_t>(field));
      v.value = s;
      break;
    }
    case FieldKind::kNested: throw std::logic_error("readPrimitive on nested field");
  }
  return v;
}

void decodeMessage(Reader& r, const MessageDefinitionSet& defs, const MessageDefinition& def,
                   const std::string& path, MessageValue& out);

MessageValue decodeElement(Reader& r, const MessageDefinitionSet& defs, const FieldDefinition& f,
                           const std::string& path) {
  if (f.kind == FieldKind::kNested) {
    MessageValue v;
    decodeMessage(r, defs, defs.type(f.nested_type), path, v);
    return v;
  }
  return readPrimitive(r, f.kind, path);
}

void decodeMessage(Reader& r, const MessageDefinitionSet& defs, const MessageDefinition& def,
                   const std::string& path, MessageValue& out) {
  MessageValue::Fields fields;
  fields.reserve(def.fields.size());
  for (const auto& f : def.fields) {
    const std::string fp = path.empty() ? f.name : path + "." + f.name;
    if (f.array == FieldDefinition::Array::kNone) {
      fields.emplace_back(f.name, decodeElement(r, defs, f, fp));
      continue;
    }
    std::size_t n = f.array_size;
    if (f.array != FieldDefinition::Array::kFixed) {
      const std::size_t min_size = f.kind == FieldKind::kNested ? 0 : std::max<std::size_t>(1, primitiveSize(f.kind));
      n = r.count(fp, min_size);
      if (f.array == FieldDefinition::Array::kBounded && n > f.array_size) {
        throw InputError("CDR sequence '" + fp + "' has " + std::to_string(n) +
                         " elements, more than its bound " + std::to_string(f.array_size));
      }
    }
    MessageValue v;
    if (isByteLike(f.kind)) {
      v.value = r.readBytes(n, fp);
    } else {
      MessageValue::Array arr;
      arr.reserve(std::min<std::size_t>(n, 1u << 16));
      for (std::size_t i = 0; i < n; ++i) arr.push_back(decodeElement(r, defs, f, fp));
      v.value = std::move(arr);
    }
    fields.emplace_back(f.name, std::move(v));
  }
  out.value = std::move(fields);
}

// ---- encoding ----------------------------------------------------------------------------------

class Writer {
 public:
  Writer() { buf_ = {0x00, 0x01, 0x00, 0x00}; }
  void align(std::size_t n) {
    while ((buf_.size() - kHeader) % n) buf_.push_back(0);
  }
  template <class T>
  void write(T v) {
    align(sizeof(T));
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    buf_.insert(buf_.end(), p, p + sizeof(T));
  }
  void writeString(const std::string& s) {
    write<std::uint32_t>(static_cast<std::uint32_t>(s.size() + 1));
    buf_.insert(buf_.end(), s.begin(), s.end());
    buf_.push_back(0);
  }
  void writeBytes(const std::vector<std::uint8_t>& b) { buf_.insert(buf_.end(), b.begin(), b.end()); }
  std::vector<std::uint8_t> take() { return std::move(buf_); }

 private:
  std::vector<std::uint8_t> buf_;
};

template <class T>
T asNumber(const MessageValue& v, const std::string& path) {
  if (auto p = std::get_if<std::int64_t>(&v.value)) return static_cast<T>(*p);
  if (auto p = std::get_if<std::uint64_t>(&v.value)) return static_cast<T>(*p);
  if (auto p = std::get_if<double>(&v.value)) return static_cast<T>(*p);
  if (auto p = std::get_if<bool>(&v.value)) return static_cast<T>(*p);
  throw std::invalid_argument("field '" + path + "' is not a number");
}

void encodeMessage(Writer& w, const MessageDefinitionSet& defs, const MessageDefinition& def,
                   const MessageValue& v, const std::string& path);

void encodeElement(Writer& w, const MessageDefinitionSet& defs, const FieldDefinition& f,
                   const MessageValue& v, const std::string& path) {
  switch (f.kind) {
    case FieldKind::kBool: w.write<std::uint8_t>(asNumber<std::uint8_t>(v, path) ? 1 : 0); break;
    case FieldKind::kByte: case FieldKind::kChar: case FieldKind::kUint8:
      w.write<std::uint8_t>(asNumber<std::uint8_t>(v, path)); break;
    case FieldKind::kInt8: w.write<std::int8_t>(asNumber<std::int8_t>(v, path)); break;
    case FieldKind::kInt16: w.write<std::int16_t>(asNumber<std::int16_t>(v, path)); break;
    case FieldKind::kUint16: w.write<std::uint16_t>(asNumber<std::uint16_t>(v, path)); break;
    case FieldKind::kInt32: w.write<std::int32_t>(asNumber<std::int32_t>(v, path)); break;
    case FieldKind::kUint32: w.write<std::uint32_t>(asNumber<std::uint32_t>(v, path)); break;
    case FieldKind::kInt64: w.write<std::int64_t>(asNumber<std::int64_t>(v, path)); break;
    case FieldKind::kUint64: w.write<std::uint64_t>(asNumber<std::uint64_t>(v, path)); break;
    case FieldKind::kFloat32: w.write<float>(asNumber<float>(v, path)); break;
    case FieldKind::kFloat64: w.write<double>(asNumber<double>(v, path)); break;
    case FieldKind::kString: case FieldKind::kWString: {
      const auto* s = std::get_if<std::string>(&v.value);
      if (!s) throw std::invalid_argument("field '" + path + "' is not a string");
      if (f.kind == FieldKind::kString) {
        w.writeString(*s);
      } else {
        w.write<std::uint32_t>(static_cast<std::uint32_t>(s->size()));
        for (char c : *s) w.write<std::uint32_t>(static_cast<unsigned char>(c));
      }
      break;
    }
    case FieldKind::kNested: encodeMessage(w, defs, defs.type(f.nested_type), v, path); break;
  }
}

void encodeMessage(Writer& w, const MessageDefinitionSet& defs, const MessageDefinition& def,
                   const MessageValue& v, const std::string& path) {
  const auto* fields = std::get_if<MessageValue::Fields>(&v.value);
  if (!fields || fields->size() != def.fields.size()) {
    throw std::invalid_argument("value at '" + path + "' does not match " + def.name);
  }
  for (std::size_t i = 0; i < def.fields.size(); ++i) {
    const auto& f = def.fields[i];
    const auto& fv = (*fields)[i].second;
    const std::string fp = path.empty() ? f.name : path + "." + f.name;
    if (f.array == FieldDefinition::Array::kNone) {
      encodeElement(w, defs, f, fv, fp);
      continue;
    }
    std::size_t n = 0;
    if (const auto* b = std::get_if<MessageValue::Bytes>(&fv.value)) {
      n = b->size();
    } else if (const auto* a = std::get_if<MessageValue::Array>(&fv.value)) {
      n = a->size();
    } else {
      throw std::invalid_argument("field '" + fp + "' is not an array");
    }
    if (f.array == FieldDefinition::Array::kFixed && n != f.array_size) {
      throw std::invalid_argument("field '" + fp + "' needs " + std::to_string(f.array_size) +
                                  " elements, has " + std::to_string(n));
    }
    if (f.array != FieldDefinition::Array::kFixed) w.write<std::uint32_t>(static_cast<std::uint32_t>(n));
    if (const auto* b = std::get_if<MessageValue::Bytes>(&fv.value)) {
      w.writeBytes(*b);
    } else {
      for (const auto& e : std::get<MessageValue::Array>(fv.value)) encodeElement(w, defs, f, e, fp);
    }
  }
}

}  // namespace

MessageValue CdrCodec::decode(const std::uint8_t* data, std::size_t size) const {
  if (size < kHeader) {
    throw InputError("CDR payload of " + std::to_string(size) + " bytes is shorter than its header");
  }
  // Encapsulation ids: 0x0000 CDR_BE, 0x0001 CDR_LE (plain CDR, what ROS 2 sends).
  if (data[0] != 0x00 || (data[1] != 0x00 && data[1] != 0x01)) {
    throw InputError("unsupported CDR encapsulation 0x" +
                     std::to_string(data[0]) + "/" + std::to_string(data[1]) +
                     " (expected plain CDR, 0x0000 or 0x0001)");
  }
  Reader r(data, size, data[1] == 0x01);
  r.skipHeader();
  MessageValue out;
  decodeMessage(r, defs_, defs_.root(), "", out);
  return out;
}

std::vector<std::uint8_t> CdrCodec::encode(const MessageValue& value) const {
  Writer w;
  encodeMessage(w, defs_, defs_.root(), value, "");
  return w.take();
}

const MessageValue& MessageValue::operator[](const std::string& name) const {
  for (const auto& [n, v] : std::get<Fields>(value)) {
    if (n == name) return v;
  }
  throw std::out_of_range("no field '" + name + "'");
}

}  // namespace mcvio::rosmsg
