#include "mcvio/rosmsg/message_definition.hpp"

#include <algorithm>
#include <cctype>
#include <sstream>

#include "mcvio/core/input_error.hpp"

namespace mcvio::rosmsg {
namespace {

const std::map<std::string, FieldKind, std::less<>>& primitiveKinds() {
  static const std::map<std::string, FieldKind, std::less<>> kinds = {
      {"bool", FieldKind::kBool},       {"byte", FieldKind::kByte},
      {"char", FieldKind::kChar},       {"int8", FieldKind::kInt8},
      {"uint8", FieldKind::kUint8},     {"int16", FieldKind::kInt16},
      {"uint16", FieldKind::kUint16},   {"int32", FieldKind::kInt32},
      {"uint32", FieldKind::kUint32},   {"int64", FieldKind::kInt64},
      {"uint64", FieldKind::kUint64},   {"float32", FieldKind::kFloat32},
      {"float64", FieldKind::kFloat64}, {"string", FieldKind::kString},
      {"wstring", FieldKind::kWString}};
  return kinds;
}

std::string trim(std::string_view s) {
  std::size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return std::string(s.substr(b, e - b));
}

std::string packageOf(const std::string& type) { return type.substr(0, type.find('/')); }

// "Pose" in package geometry_msgs, "geometry_msgs/Pose" and "geometry_msgs/msg/Pose" all name
// geometry_msgs/msg/Pose.
std::string qualify(const std::string& type, const std::string& pkg) {
  const auto n = std::count(type.begin(), type.end(), '/');
  if (n == 0) return pkg + "/msg/" + type;
  if (n == 1) return type.substr(0, type.find('/')) + "/msg/" + type.substr(type.find('/') + 1);
  return type;
}

std::uint32_t parseCount(const std::string& s, const std::string& where) {
  if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos) {
    throw InputError(where + ": bad size '" + s + "'");
  }
  return static_cast<std::uint32_t>(std::stoul(s));
}

FieldDefinition parseField(const std::string& type_token, const std::string& name,
                           const std::string& pkg, const std::string& where) {
  FieldDefinition f;
  f.name = name;
  std::string t = type_token;
  if (const auto br = t.find('['); br != std::string::npos) {
    if (t.back() != ']') throw InputError(where + ": unclosed '[' in '" + type_token + "'");
    std::string inner = t.substr(br + 1, t.size() - br - 2);
    t = t.substr(0, br);
    if (inner.empty()) {
      f.array = FieldDefinition::Array::kUnbounded;
    } else if (inner.rfind("<=", 0) == 0) {
      f.array = FieldDefinition::Array::kBounded;
      f.array_size = parseCount(inner.substr(2), where);
    } else {
      f.array = FieldDefinition::Array::kFixed;
      f.array_size = parseCount(inner, where);
    }
  }
  if (const auto le = t.find("<="); le != std::string::npos) {
    f.string_bound = parseCount(t.substr(le + 2), where);
    t = t.substr(0, le);
    if (t != "string" && t != "wstring") {
      throw InputError(where + ": only strings take a <=N bound, not '" + t + "'");
    }
  }
  const auto& prim = primitiveKinds();
  if (auto it = prim.find(t); it != prim.end()) {
    f.kind = it->second;
  } else {
    for (char c : t) {
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '/') {
        throw InputError(where + ": bad type name '" + type_token + "'");
      }
    }
    f.kind = FieldKind::kNested;
    f.nested_type = qualify(t, pkg);
  }
  return f;
}

MessageDefinition parseOne(const std::string& type, std::string_view text, int first_line) {
  MessageDefinition def;
  def.name = type;
  const std::string pkg = packageOf(type);
  std::istringstream in{std::string(text)};
  std::string line;
  int lineno = first_line;
  while (std::getline(in, line)) {
    const std::string where = type + " line " + std::to_string(lineno++);
    const auto hash = line.find('#');
    std::string body = trim(hash == std::string::npos ? line : line.substr(0, hash));
    if (body.empty()) continue;
    std::istringstream tok(body);
    std::string type_token, name;
    tok >> type_token >> name;
    if (name.empty()) throw InputError(where + ": expected '<type> <name>', got '" + body + "'");
    // Constants ("uint8 FLOAT32=7" or "uint8 FLOAT32 = 7") carry no wire data.
    if (body.find('=') != std::string::npos &&
        body.find('=') > body.find(name) && type_token.find("<=") == std::string::npos) {
      bool upper = true;
      for (char c : name.substr(0, name.find('='))) upper = upper && !std::islower(static_cast<unsigned char>(c));
      if (upper) continue;
    }
    def.fields.push_back(parseField(type_token, name, pkg, where));
  }
  return def;
}

}  // namespace

std::size_t primitiveSize(FieldKind kind) {
  switch (kind) {
    case FieldKind::kBool: case FieldKind::kByte: case FieldKind::kChar:
    case FieldKind::kInt8: case FieldKind::kUint8: return 1;
    case FieldKind::kInt16: case FieldKind::kUint16: return 2;
    case FieldKind::kInt32: case FieldKind::kUint32: case FieldKind::kFloat32: return 4;
    case FieldKind::kInt64: case FieldKind::kUint64: case FieldKind::kFloat64: return 8;
    default: return 0;
  }
}

MessageDefinitionSet MessageDefinitionSet::parse(std::string_view root_type,
                                                 std::string_view full_definition) {
  MessageDefinitionSet set;
  set.root_ = std::string(root_type);
  // Split at separator lines of '=' followed by "MSG: pkg/Name".
  std::string current = set.root_;
  std::string chunk;
  int chunk_first_line = 1, lineno = 0;
  std::istringstream in{std::string(full_definition)};
  std::string line;
  bool expect_msg = false;
  auto flush = [&] {
    set.types_[current] = parseOne(current, chunk, chunk_first_line);
    chunk.clear();
  };
  while (std::getline(in, line)) {
    ++lineno;
    const std::string t = trim(line);
    if (t.size() >= 3 && t.find_first_not_of('=') == std::string::npos) {
      flush();
      expect_msg = true;
      continue;
    }
    if (expect_msg) {
      if (t.rfind("MSG:", 0) != 0) {
        throw InputError(set.root_ + " definition line " + std::to_string(lineno) +
                         ": expected 'MSG: pkg/Name' after a separator line");
      }
      current = qualify(trim(t.substr(4)), packageOf(set.root_));
      chunk_first_line = lineno + 1;
      expect_msg = false;
      continue;
    }
    chunk += line;
    chunk += '\n';
  }
  flush();
  // Every nested type must be defined.
  for (const auto& [name, def] : set.types_) {
    for (const auto& f : def.fields) {
      if (f.kind == FieldKind::kNested && !set.types_.count(f.nested_type)) {
        throw InputError(name + ": field '" + f.name + "' uses type " + f.nested_type +
                         " whose definition is missing");
      }
    }
  }
  return set;
}

const MessageDefinition& MessageDefinitionSet::type(const std::string& name) const {
  auto it = types_.find(name);
  if (it == types_.end()) throw InputError("no definition of message type " + name);
  return it->second;
}

}  // namespace mcvio::rosmsg
