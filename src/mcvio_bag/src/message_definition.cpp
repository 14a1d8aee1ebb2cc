#include "mcvio/bag/message_definition.hpp"

#include <cctype>
#include <set>
#include <sstream>

#include "mcvio/core/input_error.hpp"

namespace mcvio::bag {

namespace {

const std::set<std::string>& primitives() {
  static const std::set<std::string> p = {
      "bool",  "byte",   "char",  "float32", "float64", "int8",    "uint8", "int16",   "uint16",
      "int32", "uint32", "int64", "uint64",  "string",  "wstring", "time",  "duration"};
  return p;
}

std::string trim(const std::string& s) {
  std::size_t b = 0;
  std::size_t e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

bool isIdentifier(const std::string& s) {
  if (s.empty() || !std::isalpha(static_cast<unsigned char>(s[0]))) return false;
  for (char c : s) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  }
  return true;
}

bool isSeparator(const std::string& line) {
  if (line.size() < 3) return false;
  for (char c : line) {
    if (c != '=') return false;
  }
  return true;
}

/// "pkg/msg/Name" and "pkg/Name" name the same type; keep the short form as the key.
std::string normalizeType(const std::string& t) {
  const auto first = t.find('/');
  const auto last = t.rfind('/');
  if (first != std::string::npos && first != last) return t.substr(0, first) + t.substr(last);
  return t;
}

std::string packageOf(const std::string& t) {
  const auto slash = t.find('/');
  return slash == std::string::npos ? std::string() : t.substr(0, slash);
}

bool parseSize(const std::string& s, std::size_t& out) {
  if (s.empty() || s.size() > 18) return false;
  for (char c : s) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  }
  out = static_cast<std::size_t>(std::stoull(s));
  return true;
}

struct Section {
  std::string name;
  std::vector<std::pair<int, std::string>> lines;  // (1-based line number in text, text)
};

[[noreturn]] void fail(const std::string& root, int line, const std::string& why) {
  std::ostringstream os;
  os << "message definition of '" << root << "', line " << line << ": " << why;
  throw InputError(os.str());
}

MessageField parseLine(const std::string& root, int lineno, const std::string& raw,
                       const std::string& package) {
  // Split off the type token.
  std::string line = raw;
  std::size_t i = 0;
  while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
  std::string type = line.substr(0, i);
  std::string rest = trim(line.substr(i));
  MessageField f;
  // Array suffix.
  const auto bracket = type.find('[');
  if (bracket != std::string::npos) {
    if (type.back() != ']') fail(root, lineno, "malformed array type '" + type + "'");
    std::string inside = type.substr(bracket + 1, type.size() - bracket - 2);
    type = type.substr(0, bracket);
    f.is_array = true;
    if (inside.rfind("<=", 0) == 0) {
      f.is_bounded = true;
      if (!parseSize(inside.substr(2), f.array_length)) {
        fail(root, lineno, "bad array bound '" + inside + "'");
      }
    } else if (!inside.empty() && !parseSize(inside, f.array_length)) {
      fail(root, lineno, "bad array length '" + inside + "'");
    }
  }
  // Bounded strings.
  const auto le = type.find("<=");
  if (le != std::string::npos) {
    const std::string base = type.substr(0, le);
    if ((base != "string" && base != "wstring") ||
        !parseSize(type.substr(le + 2), f.string_bound)) {
      fail(root, lineno, "bad bounded type '" + type + "'");
    }
    type = base;
  }
  if (type.empty()) fail(root, lineno, "missing type");
  if (primitives().count(type) != 0) {
    f.type = type;
  } else {
    // A nested type: "pkg/Name", "pkg/msg/Name" or "Name" in the same package.
    std::string t = type;
    if (t.find('/') == std::string::npos) {
      t = (t == "Header") ? std::string("std_msgs/Header") : package + "/" + t;
    }
    const auto parts_ok = [&] {
      std::size_t start = 0;
      int parts = 0;
      while (true) {
        const auto slash = t.find('/', start);
        const std::string part =
            t.substr(start, slash == std::string::npos ? slash : slash - start);
        if (!isIdentifier(part)) return false;
        ++parts;
        if (slash == std::string::npos) break;
        start = slash + 1;
      }
      return parts == 2 || parts == 3;
    }();
    if (!parts_ok || (package.empty() && type.find('/') == std::string::npos)) {
      fail(root, lineno, "unknown or malformed type '" + type + "'");
    }
    f.type = normalizeType(t);
    f.is_complex = true;
  }
  // Name, then a constant ("NAME=value") or an optional default value.
  std::size_t j = 0;
  while (j < rest.size() && (std::isalnum(static_cast<unsigned char>(rest[j])) || rest[j] == '_')) {
    ++j;
  }
  f.name = rest.substr(0, j);
  if (!isIdentifier(f.name))
    fail(root, lineno, "missing or invalid field name after '" + type + "'");
  std::string tail = trim(rest.substr(j));
  if (!tail.empty() && tail[0] == '=') {
    if (f.is_array || f.is_complex)
      fail(root, lineno, "constant '" + f.name + "' must be a primitive");
    f.is_constant = true;
    std::string value = trim(tail.substr(1));
    if (f.type != "string" && f.type != "wstring") value = trim(value.substr(0, value.find('#')));
    if (value.empty()) fail(root, lineno, "constant '" + f.name + "' has no value");
    f.value = value;
  } else {
    tail = trim(tail.substr(0, tail.find('#')));
    if (!tail.empty() && f.is_complex)
      fail(root, lineno, "nested field '" + f.name + "' cannot have a default");
    f.value = tail;
  }
  return f;
}

}  // namespace

std::vector<MessageType> MessageDefinitionParser::parse(const std::string& type_name,
                                                        const std::string& text) {
  if (type_name.empty()) throw InputError("message definition: empty type name");
  if (text.find('\0') != std::string::npos) fail(type_name, 1, "contains a NUL byte");
  std::vector<Section> sections(1);
  sections[0].name = type_name;
  std::istringstream in(text);
  std::string line;
  int lineno = 0;
  bool expect_msg = false;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string t = trim(line);
    if (isSeparator(t)) {
      expect_msg = true;
      continue;
    }
    if (expect_msg) {
      if (t.empty()) continue;
      if (t.rfind("MSG:", 0) != 0)
        fail(type_name, lineno, "expected 'MSG: pkg/Name' after a separator line");
      Section s;
      s.name = trim(t.substr(4));
      if (s.name.find('/') == std::string::npos)
        fail(type_name, lineno, "nested type '" + s.name + "' has no package");
      sections.push_back(std::move(s));
      expect_msg = false;
      continue;
    }
    // Comment-only and blank lines carry nothing.
    const std::string code = trim(t.substr(0, t[0] == '#' ? 0 : std::string::npos));
    if (code.empty() || code[0] == '#') continue;
    sections.back().lines.emplace_back(lineno, code);
  }
  if (expect_msg) fail(type_name, lineno, "separator line without a following 'MSG:' line");

  std::vector<MessageType> types;
  std::set<std::string> defined;
  for (const auto& s : sections) {
    MessageType mt;
    mt.name = s.name;
    const std::string package = packageOf(s.name);
    std::set<std::string> names;
    for (const auto& [n, code] : s.lines) {
      MessageField f = parseLine(type_name, n, code, package);
      if (!names.insert(f.name).second) fail(type_name, n, "duplicate field name '" + f.name + "'");
      mt.fields.push_back(std::move(f));
    }
    if (!defined.insert(normalizeType(s.name)).second && &s != &sections[0]) {
      throw InputError("message definition of '" + type_name + "': type '" + s.name +
                       "' is defined twice");
    }
    types.push_back(std::move(mt));
  }
  for (const auto& mt : types) {
    for (const auto& f : mt.fields) {
      if (f.is_complex && defined.count(f.type) == 0) {
        throw InputError("message definition of '" + type_name + "': field '" + f.name + "' of '" +
                         mt.name + "' uses type '" + f.type + "' whose definition is not included");
      }
    }
  }
  return types;
}

}  // namespace mcvio::bag
