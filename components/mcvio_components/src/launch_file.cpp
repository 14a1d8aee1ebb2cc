#include "mcvio/components/launch_file.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>
#include <stdexcept>

#include "mcvio/conflict/conflict_options.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/core/topic_remapping.hpp"
#include "mcvio/core/yaml_fields.hpp"
#include "mcvio/core/yaml_file.hpp"
#include "mcvio/dds/topic_names.hpp"
#include "mcvio/pipeline/vio_pipeline.hpp"

namespace mcvio::components {

namespace {

bool validArgumentName(const std::string& name) {
  if (name.empty() || !(std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_')) return false;
  return std::all_of(name.begin(), name.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

std::string joined(const std::vector<std::string>& words) {
  std::string s;
  for (const auto& w : words) s += (s.empty() ? "" : ", ") + w;
  return s.empty() ? "none" : s;
}

// ROS 2 launch's conditions: true/false (and 1/0), any case.
bool conditionValue(const std::string& text, bool* value) {
  std::string t = text;
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (t == "true" || t == "1") return *value = true, true;
  if (t == "false" || t == "0") return *value = false, true;
  return false;
}

const std::map<std::string, LaunchPlan::Kind>& kinds() {
  static const std::map<std::string, LaunchPlan::Kind> k = {{"player", LaunchPlan::Kind::kPlayer},
                                                            {"frontend", LaunchPlan::Kind::kFrontend},
                                                            {"backend", LaunchPlan::Kind::kBackend},
                                                            {"recorder", LaunchPlan::Kind::kRecorder}};
  return k;
}

// ROS 2 launch's `remap:` list: "FROM:=TO" strings or {from: FROM, to: TO} maps.
TopicRemapping remappingOf(const YAML::Node& list) {
  if (!list || list.IsNull()) return {};
  if (!list.IsSequence()) throw InputError("'remap' must be a list of FROM:=TO rules or {from: ..., to: ...} maps");
  std::vector<std::string> rules;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node r = list[i];
    if (r.IsScalar()) {
      rules.push_back(r.Scalar());
    } else if (r.IsMap() && r.size() == 2 && r["from"] && r["from"].IsScalar() && r["to"] && r["to"].IsScalar()) {
      rules.push_back(r["from"].Scalar() + ":=" + r["to"].Scalar());
    } else {
      throw InputError("remap[" + std::to_string(i) + "] must be FROM:=TO or a map with exactly 'from' and 'to'");
    }
  }
  return TopicRemapping::parse(rules);
}

}  // namespace

const char* LaunchPlan::kindName(Kind kind) {
  for (const auto& [name, k] : kinds())
    if (k == kind) return name.c_str();
  return "?";
}

bool LaunchPlan::has(Kind kind) const {
  return std::any_of(entries.begin(), entries.end(), [kind](const Entry& e) { return e.kind == kind; });
}

LaunchFile LaunchFile::load(const std::string& path) {
  namespace fs = std::filesystem;
  LaunchFile f;
  f.source_ = path;
  f.dirname_ = fs::absolute(fs::path(path)).parent_path().lexically_normal().string();
  f.root_ = loadYamlFile(path, "launch file");
  f.readArguments();
  return f;
}

LaunchFile LaunchFile::parse(const std::string& text, const std::string& source, const std::string& dirname) {
  LaunchFile f;
  f.source_ = source;
  f.dirname_ = dirname;
  f.root_ = parseYamlText(text, source);
  f.readArguments();
  return f;
}

void LaunchFile::readArguments() {
  if (!root_.IsMap()) throw InputError(source_ + ": a launch file is a map with 'components:' (and 'arguments:')");
  const YAML::Node& root = root_;  // the const operator[] never adds the key
  const YAML::Node arg_node = root["arguments"];
  if (!arg_node || arg_node.IsNull()) return;
  if (!arg_node.IsMap()) throw InputError(at(arg_node) + "'arguments' must be a map NAME: {default: VALUE, description: TEXT}");
  for (const auto& kv : arg_node) {
    Argument a;
    a.name = kv.first.Scalar();
    if (!validArgumentName(a.name)) throw InputError(at(kv.first) + "argument '" + a.name + "' is not a name (letters, digits, _)");
    try {
      YamlFields f(kv.second, "arguments." + a.name + ".", "launch key");
      if (f.has("default")) {
        const YAML::Node d = f.child("default");
        if (!d.IsScalar() && !d.IsNull()) throw InputError("argument '" + a.name + "': the default must be a single value");
        a.default_value = d.IsScalar() ? d.Scalar() : "";
        a.has_default = true;
      }
      f.get("description", &a.description);
      f.rejectUnknown();
    } catch (const InputError& e) {
      throw InputError(at(kv.second) + e.what());
    }
    arguments_.push_back(a);
  }
}

std::string LaunchFile::declaredNames() const {
  std::vector<std::string> names;
  for (const auto& a : arguments_) names.push_back(a.name);
  return joined(names);
}

std::string LaunchFile::at(const YAML::Node& node) const {
  const auto mark = node.Mark();
  return mark.line >= 0 ? source_ + ":" + std::to_string(mark.line + 1) + ": " : source_ + ": ";
}

std::pair<std::string, std::string> LaunchFile::parseAssignment(const std::string& text) {
  const auto pos = text.find(":=");
  if (pos == std::string::npos)
    throw InputError("launch argument '" + text + "' is not NAME:=VALUE (e.g. data:=/tmp/elevator)");
  const std::string name = text.substr(0, pos);
  if (!validArgumentName(name))
    throw InputError("launch argument '" + text + "': '" + name + "' is not a name (letters, digits, _)");
  return {name, text.substr(pos + 2)};
}

std::string LaunchFile::substitute(const std::string& text, const Values& args, const YAML::Node& where) const {
  std::string out;
  std::size_t i = 0;
  while (i < text.size()) {
    const auto open = text.find("$(", i);
    if (open == std::string::npos) {
      out += text.substr(i);
      break;
    }
    out += text.substr(i, open - i);
    const auto close = text.find(')', open);
    if (close == std::string::npos)
      throw InputError(at(where) + "'" + text + "': a substitution '$(' without its ')'");
    std::istringstream words(text.substr(open + 2, close - open - 2));
    std::vector<std::string> w;
    for (std::string s; words >> s;) w.push_back(s);
    const std::string what = "'$(" + text.substr(open + 2, close - open - 2) + ")'";
    if (w.empty()) throw InputError(at(where) + what + " is empty; use $(arg NAME), $(env NAME [DEFAULT]) or $(dirname)");
    if (w[0] == "arg") {
      if (w.size() != 2) throw InputError(at(where) + what + ": $(arg NAME) takes one name");
      const auto it = args.find(w[1]);
      if (it == args.end())
        throw InputError(at(where) + what + ": no argument '" + w[1] + "' is declared under 'arguments:' (declared: " +
                         declaredNames() + ")");
      out += it->second;
    } else if (w[0] == "env") {
      if (w.size() != 2 && w.size() != 3) throw InputError(at(where) + what + ": $(env NAME) or $(env NAME DEFAULT)");
      const char* v = std::getenv(w[1].c_str());
      if (v) {
        out += v;
      } else if (w.size() == 3) {
        out += w[2];
      } else {
        throw InputError(at(where) + what + ": environment variable " + w[1] +
                         " is not set (give a default: $(env " + w[1] + " DEFAULT))");
      }
    } else if (w[0] == "dirname") {
      if (w.size() != 1) throw InputError(at(where) + what + ": $(dirname) takes nothing");
      out += dirname_;
    } else {
      throw InputError(at(where) + what + ": unknown substitution '" + w[0] +
                       "' (known: $(arg NAME), $(env NAME [DEFAULT]), $(dirname))");
    }
    i = close + 1;
  }
  return out;
}

YAML::Node LaunchFile::substituted(const YAML::Node& node, const Values& args) const {
  if (node.IsScalar()) {
    // A plain "1.5" or "true" stays what it was; only text with $( changes.
    if (node.Scalar().find("$(") == std::string::npos) return node;
    return YAML::Node(substitute(node.Scalar(), args, node));
  }
  if (node.IsSequence()) {
    YAML::Node out(YAML::NodeType::Sequence);
    for (const auto& v : node) out.push_back(substituted(v, args));
    return out;
  }
  if (node.IsMap()) {
    YAML::Node out(YAML::NodeType::Map);
    for (const auto& kv : node) out[kv.first.Scalar()] = substituted(kv.second, args);
    return out;
  }
  return node;
}

LaunchPlan LaunchFile::resolve(const std::map<std::string, std::string>& values) const {
  LaunchPlan plan;
  plan.source = source_;
  YamlFields top(root_, "", "launch key");

  // Arguments first: they are what the rest refers to.
  Values args;
  const std::vector<Argument>& declared = arguments_;
  const YAML::Node arg_node = top.has("arguments") ? top.child("arguments") : YAML::Node();
  for (const auto& [name, value] : values) {
    if (std::none_of(declared.begin(), declared.end(), [&](const Argument& a) { return a.name == name; }))
      throw InputError(source_ + ": no argument '" + name + "' is declared (declared: " + declaredNames() + ")");
  }
  std::vector<std::string> missing;
  for (const auto& a : declared) {
    const auto it = values.find(a.name);
    if (it != values.end()) {
      args[a.name] = it->second;
    } else if (a.has_default) {
      args[a.name] = a.default_value;
    } else {
      missing.push_back(a.name + ":=VALUE" + (a.description.empty() ? "" : " (" + a.description + ")"));
    }
  }
  if (!missing.empty()) throw InputError(source_ + ": give the required argument(s) " + joined(missing));
  // A default may name another argument ($(arg data) as the calibration's default).
  for (const auto& a : declared) {
    if (values.count(a.name) == 0 && args[a.name].find("$(") != std::string::npos) {
      Values earlier;
      for (const auto& [k, v] : args)
        if (k != a.name) earlier[k] = v;
      args[a.name] = substitute(args[a.name], earlier, arg_node[a.name]);
    }
  }

  if (top.has("exit_when_played")) {
    const YAML::Node exit_node = top.child("exit_when_played");
    if (!exit_node.IsScalar() || !conditionValue(substitute(exit_node.Scalar(), args, exit_node), &plan.exit_when_played))
      throw InputError(at(exit_node) + "'exit_when_played' must be true or false");
  }
  if (top.has("drain_timeout")) {
    const YAML::Node drain = top.child("drain_timeout");
    YAML::Node m(YAML::NodeType::Map);
    m["drain_timeout"] = substituted(drain, args);
    YamlFields d(m, "", "launch key");
    try {
      d.get("drain_timeout", &plan.drain_timeout_s);
    } catch (const InputError& e) {
      throw InputError(at(drain) + e.what());
    }
    if (!(plan.drain_timeout_s > 0 && plan.drain_timeout_s <= 86400))
      throw InputError(at(drain) + "'drain_timeout' must be in (0, 86400] seconds");
  }
  const YAML::Node list = top.has("components") ? top.child("components") : YAML::Node();
  try {
    top.rejectUnknown();
  } catch (const InputError& e) {
    throw InputError(source_ + ": " + e.what());
  }
  if (!list || !list.IsSequence() || list.size() == 0)
    throw InputError(source_ + ": 'components:' must list at least one component (player, frontend, backend, recorder)");

  std::set<std::string> names;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node n = list[i];
    if (!n.IsMap()) throw InputError(at(n) + "components[" + std::to_string(i) + "] must be a map with 'component: KIND'");
    // Conditions first: a component left out may name arguments that only matter when it runs.
    bool run = true;
    for (const char* key : {"if", "unless"}) {
      const YAML::Node c = n[key];
      if (!c) continue;
      bool v = false;
      const std::string text = c.IsScalar() ? substitute(c.Scalar(), args, c) : std::string("<not a value>");
      if (!conditionValue(text, &v))
        throw InputError(at(c) + "components[" + std::to_string(i) + "]." + key + " is '" + text + "'; it must be true or false");
      run = run && (std::string(key) == "if" ? v : !v);
    }
    if (!run) continue;
    auto e = entry(n, i, args);
    if (!names.insert(e.node_namespace + "/" + e.name).second)
      throw InputError(at(n) + "two components are named '" + e.name + "' in " + e.node_namespace + "; give one a 'name:'");
    plan.entries.push_back(std::move(e));
  }
  if (plan.entries.empty()) throw InputError(source_ + ": every component is switched off by its if/unless");
  return plan;
}

LaunchPlan::Entry LaunchFile::entry(const YAML::Node& raw, std::size_t index, const Values& args) const {
  const std::string where = at(raw);
  const std::string prefix = "components[" + std::to_string(index) + "].";
  const YAML::Node node = substituted(raw, args);
  YamlFields f(node, prefix, "launch key");
  LaunchPlan::Entry e;
  std::string kind;
  f.get("component", &kind);
  if (kind.empty()) throw InputError(where + prefix + "component is missing (player, frontend, backend or recorder)");
  const auto k = kinds().find(kind);
  if (k == kinds().end())
    throw InputError(where + prefix + "component '" + kind + "' is not a component (player, frontend, backend or recorder)");
  e.kind = k->second;
  e.name = kind;
  f.has("if");
  f.has("unless");
  const auto fail = [&](const std::string& what) { throw InputError(where + "component '" + e.name + "': " + what); };
  try {
    f.get("name", &e.name);
    f.get("namespace", &e.node_namespace);
    if (e.node_namespace.empty() || e.node_namespace[0] != '/') fail("namespace '" + e.node_namespace + "' must start with '/'");
    dds::validateNodeName(e.name);
    if (f.has("remap")) {
      if (e.kind == LaunchPlan::Kind::kRecorder)
        fail("'remap' is for players, frontends and backends: a recorder records topics under their own names");
      e.remapping = remappingOf(node["remap"]);
    }
    f.get("respawn", &e.respawn);
    f.get("respawn_delay", &e.respawn_delay_s);
    if (!(e.respawn_delay_s >= 0 && e.respawn_delay_s <= 3600)) fail("'respawn_delay' must be in [0, 3600] seconds");
    if (e.respawn && (e.kind == LaunchPlan::Kind::kPlayer || e.kind == LaunchPlan::Kind::kRecorder))
      fail(std::string("'respawn' is for frontends and backends: a ") +
           (e.kind == LaunchPlan::Kind::kPlayer ? "player started again would play its input again"
                                                : "recorder started again could not reopen its bag"));
    switch (e.kind) {
      case LaunchPlan::Kind::kPlayer: {
        auto& p = e.player;
        f.get("input", &e.input);
        f.get("topics", &e.topics);
        f.get("rate", &p.rate);
        f.get("lossless", &p.lossless);
        f.get("loop", &p.loop);
        f.get("start", &p.start_s);
        f.get("duration", &p.duration_s);
        f.get("max_gap", &p.max_gap_s);
        f.get("wait_for_readers", &p.wait_for_readers_s);
        f.get("progress", &p.progress);
        if (e.input.empty()) fail("'input' (a EuRoC folder or a bag) is missing or empty");
        for (const auto& t : e.topics) dds::validateTopicName(t);
        p.validate();
        break;
      }
      case LaunchPlan::Kind::kFrontend: {
        auto& o = e.frontend;
        std::string config;
        f.get("calibration", &o.calibration_dir);
        f.get("config", &config);
        f.get("tracks_image", &o.publish_tracks_image);
        f.get("lossless", &o.lossless);
        f.get("max_queued_pairs", &o.max_queued_pairs);
        f.get("image_transport", &o.image_transport);
        if (o.calibration_dir.empty()) fail("'calibration' (a EuRoC folder with the cameras' sensor.yaml) is missing or empty");
        if (o.max_queued_pairs == 0) fail("'max_queued_pairs' must be at least 1");
        if (o.image_transport != "raw" && o.image_transport != "compressed")
          fail("'image_transport' is '" + o.image_transport + "'; it must be raw or compressed");
        if (!config.empty()) o.tracker = pipeline::VioPipelineOptions::fromYamlFile(config).frontend;
        break;
      }
      case LaunchPlan::Kind::kBackend: {
        auto& o = e.backend;
        std::string config, mode;
        f.get("calibration", &o.calibration_dir);
        f.get("config", &config);
        f.get("mode", &mode);
        f.get("lossless", &o.lossless);
        f.get("world_frame", &o.world_frame);
        f.get("body_frame", &o.body_frame);
        f.get("secondary_frame", &o.secondary_frame);
        f.get("landmarks_every", &o.landmarks_every_n_frames);
        f.get("path_max", &o.max_path_poses);
        f.get("max_imu_wait", &o.max_imu_wait_s);
        f.get("max_queued_frames", &o.max_queued_frames);
        if (o.calibration_dir.empty()) fail("'calibration' (a EuRoC folder with the sensors' sensor.yaml) is missing or empty");
        if (!config.empty()) o.estimator = pipeline::VioPipelineOptions::fromYamlFile(config).estimator;
        if (!mode.empty()) o.estimator.conflict.mode = conflict::resolutionModeFromString(mode, "'mode'");
        o.validate();
        break;
      }
      case LaunchPlan::Kind::kRecorder: {
        auto& r = e.recorder;
        std::string storage = "mcap", compression = "zstd";
        double max_duration = 0;
        f.get("output", &e.output);
        f.get("topics", &r.topics);
        f.get("all", &r.all);
        f.get("regex", &r.regex);
        f.get("storage", &storage);
        f.get("compression", &compression);
        f.get("max_bag_size", &r.bag.max_bagfile_size);
        f.get("max_bag_duration", &max_duration);
        if (e.output.empty()) fail("'output' (the bag directory to create) is missing or empty");
        if (storage != "mcap" && storage != "sqlite3") fail("storage '" + storage + "' is not mcap or sqlite3");
        if (compression != "zstd" && compression != "lz4" && compression != "none")
          fail("compression '" + compression + "' is not zstd, lz4 or none");
        if (!(max_duration >= 0)) fail("'max_bag_duration' must be >= 0 seconds");
        for (const auto& t : r.topics) dds::validateTopicName(t);
        r.bag.storage = storage;
        r.bag.compression = compression == "zstd" ? bag::Compression::Zstd
                            : compression == "lz4" ? bag::Compression::Lz4 : bag::Compression::None;
        r.bag.max_bagfile_duration = fromSeconds(max_duration);
        r.validate();
        break;
      }
    }
    f.rejectUnknown();
  } catch (const InputError& ex) {
    const std::string what = ex.what();
    if (what.rfind(source_, 0) == 0) throw;  // already names the launch file
    // An options file named by 'config' names itself; the rest gets the launch file's line.
    throw InputError(where + "component '" + e.name + "': " + what);
  } catch (const std::invalid_argument& ex) {
    throw InputError(where + "component '" + e.name + "': " + ex.what());
  }
  return e;
}

std::string LaunchFile::keysHelp() {
  return "Keys of every component: component (player, frontend, backend, recorder), name (node name, default: the\n"
         "kind), namespace (default /mcvio), if / unless (true or false), remap (not recorders: a list of\n"
         "FROM:=TO or {from: FROM, to: TO}, ROS 2's topic remapping); frontends and backends also respawn\n"
         "(true: with --processes, start it again when it ends while the launch runs) and respawn_delay (s).\n"
         "  player    input (EuRoC folder or bag, required), topics (bags: a list), rate, lossless, loop, start,\n"
         "            duration, max_gap, wait_for_readers, progress\n"
         "  frontend  calibration (EuRoC folder or Kalibr camchain-imucam, required), config (YAML with frontend:), tracks_image, lossless,\n"
         "            max_queued_pairs, image_transport (raw, compressed)\n"
         "  backend   calibration (required), config (YAML with estimator:), mode (reference, imu, selective,\n"
         "            auto), lossless, world_frame, body_frame, secondary_frame, landmarks_every, path_max,\n"
         "            max_imu_wait, max_queued_frames\n"
         "  recorder  output (bag directory, required), topics (a list), all, regex, storage (mcap, sqlite3),\n"
         "            compression (zstd, lz4, none), max_bag_size, max_bag_duration\n"
         "The same meaning and defaults as the options of mcvio play / frontend / backend / record.";
}

}  // namespace mcvio::components
