// Configuration (config.h): declared settings, layered files.

#include "rigel/tools/config.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rigel/base/log.h"
#include "rigel/io/diffable_json.h"
#include "rigel/io/json_depth.h"
#include "rigel/io/scene_file.h"

namespace rigel::tools {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

using Type = SettingSpec::Type;

std::vector<SettingSpec> make_specs() {
  std::vector<SettingSpec> s;
  s.push_back({"log.level", Type::kString, std::string("warn"), {"trace", "debug", "info", "warn", "error", "off"}, 0, 0,
               "what the command line prints on stderr (a job's log file takes debug and above)"});
  s.push_back({"naming.template", Type::kString, std::string("{rig}_{component}_{role}{index}"), {}, 0, 0,
               "the names of built nodes: {rig}, {component} (arm_L), {name} (arm), {side} (L), {role}, {index} "
               "(empty for a single node); must hold {role} and {index}"});
  s.push_back({"data.weights", Type::kString, std::string("json"), {"json", "binary"}, 0, 0,
               "how exported skin weights are written: all in the JSON, or the arrays in a side file with a checksum"});
  s.push_back({"viewport.menuMode", Type::kString, std::string("animator"), {"animator", "rigger"}, 0, 0,
               "the web app's context menu mode at start"});
  s.push_back({"viewport.controlLineWidth", Type::kNumber, 1.0, {}, 0.5, 10, "the width of control shapes in the web app (pixels)"});
  s.push_back({"batch.jobs", Type::kInteger, std::int64_t{0}, {}, 0, 1024, "processes a local batch runs at once (0: one per core)"});
  s.push_back({"batch.partition", Type::kString, std::string(), {}, 0, 0, "the Slurm partition batch jobs go to (empty: the default)"});
  s.push_back({"publish.checks", Type::kBool, true, {}, 0, 0, "run the asset's checks (validation, regression poses) before publishing"});
  return s;
}

std::string quote(std::string_view s) {
  std::string out;  // (not "'" + std::string(s): GCC 12 warns falsely on that, -Wstringop-overflow)
  out.reserve(s.size() + 2);
  out += '\'';
  out += s;
  out += '\'';
  return out;
}

std::string takes(const SettingSpec& spec) {
  switch (spec.type) {
    case Type::kBool: return "true or false";
    case Type::kInteger: return "a whole number from " + setting_text(std::int64_t(spec.min)) + " to " + setting_text(std::int64_t(spec.max));
    case Type::kNumber: return "a number from " + setting_text(spec.min) + " to " + setting_text(spec.max);
    case Type::kString: {
      if (spec.choices.empty()) return "text";
      std::string out = "one of";
      for (std::size_t i = 0; i < spec.choices.size(); ++i) out += (i ? ", " : " ") + spec.choices[i];
      return out;
    }
  }
  return "a value";
}

// A value read from a file or the command line, checked against its spec.
Result<SettingValue> check_value(const SettingSpec& spec, const Json& j, const std::string& where) {
  auto bad = [&] {
    return Status(ErrorCode::kInvalidArgument, (where.empty() ? "" : where + ": ") + spec.key + " takes " + takes(spec))
        .with_field("value");
  };
  switch (spec.type) {
    case Type::kBool:
      if (!j.is_boolean()) return bad();
      return SettingValue(j.get<bool>());
    case Type::kInteger: {
      if (!j.is_number_integer()) return bad();
      const std::int64_t v = j.get<std::int64_t>();
      if (v < spec.min || v > spec.max) return bad();
      return SettingValue(v);
    }
    case Type::kNumber: {
      if (!j.is_number()) return bad();
      const double v = j.get<double>();
      if (!std::isfinite(v) || v < spec.min || v > spec.max) return bad();
      return SettingValue(v);
    }
    case Type::kString: {
      if (!j.is_string()) return bad();
      const std::string v = j.get<std::string>();
      if (!spec.choices.empty() && std::find(spec.choices.begin(), spec.choices.end(), v) == spec.choices.end()) return bad();
      if (spec.key == "naming.template") {
        if (v.find("{role}") == std::string::npos || v.find("{index}") == std::string::npos)
          return Status(ErrorCode::kInvalidArgument, (where.empty() ? "" : where + ": ") + "naming.template must hold {role} and {index}")
              .with_field("value");
        for (std::size_t at = v.find('{'); at != std::string::npos; at = v.find('{', at + 1)) {
          const std::size_t end = v.find('}', at);
          const std::string token = end == std::string::npos ? v.substr(at) : v.substr(at, end - at + 1);
          if (token != "{rig}" && token != "{component}" && token != "{name}" && token != "{side}" && token != "{role}" &&
              token != "{index}")
            return Status(ErrorCode::kInvalidArgument, (where.empty() ? "" : where + ": ") + "naming.template: unknown token " + token +
                                                           " (it takes {rig}, {component}, {name}, {side}, {role}, {index})")
                .with_field("value");
        }
      }
      return SettingValue(v);
    }
  }
  return bad();
}

// The file's settings object (empty for a missing file).
Result<Json> read_file(const fs::path& file) {
  std::error_code ec;
  if (file.empty() || !fs::exists(file, ec)) return Json::object();
  if (!fs::is_regular_file(file, ec)) return Status(ErrorCode::kInvalidArgument, file.string() + ": not a file");
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) return Status(ErrorCode::kIoError, file.string() + ": cannot be read");
  const std::string s = text.str();
  Result<Json> parsed = io::parse_json(s, file.string(), 16);
  if (!parsed) return parsed.status();
  Json j = std::move(*parsed);
  const std::string where = file.string();
  if (!j.is_object() || !j.contains("rigelConfig"))
    return Status(ErrorCode::kParseError, where + ": not a rigel settings file (expected {\"rigelConfig\": 1, \"settings\": {...}})");
  if (!j["rigelConfig"].is_number_integer() || j["rigelConfig"].get<std::int64_t>() < 1)
    return Status(ErrorCode::kParseError, where + ": rigelConfig: expected a format number");
  if (j["rigelConfig"].get<std::int64_t>() > kConfigFormat)
    return Status(ErrorCode::kFailedPrecondition, where + ": made by a newer rigel (settings format " +
                                                      std::to_string(j["rigelConfig"].get<std::int64_t>()) +
                                                      "; this rigel reads " + std::to_string(kConfigFormat) + ")");
  if (!j.contains("settings")) return Json::object();
  if (!j["settings"].is_object()) return Status(ErrorCode::kParseError, where + ": settings: expected an object");
  for (auto it = j["settings"].begin(); it != j["settings"].end(); ++it) {
    const SettingSpec* spec = find_setting(it.key());
    if (!spec) return Status(ErrorCode::kParseError, where + ": settings: unknown setting " + quote(it.key()));
    if (auto v = check_value(*spec, it.value(), where + ": settings"); !v)
      return Status(ErrorCode::kParseError, v.status().message());
  }
  return j["settings"];
}

}  // namespace

const std::vector<SettingSpec>& setting_specs() {
  static const std::vector<SettingSpec> specs = make_specs();
  return specs;
}

const SettingSpec* find_setting(std::string_view key) {
  for (const SettingSpec& s : setting_specs())
    if (s.key == key) return &s;
  return nullptr;
}

std::string setting_text(const SettingValue& value) {
  if (const bool* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
  if (const std::int64_t* i = std::get_if<std::int64_t>(&value)) return std::to_string(*i);
  if (const double* d = std::get_if<double>(&value)) return Json(*d).dump();
  return std::get<std::string>(value);
}

Result<SettingValue> parse_setting(const SettingSpec& spec, std::string_view text) {
  Json j;
  switch (spec.type) {
    case Type::kBool:
      if (text == "true" || text == "false") j = text == "true";
      break;
    case Type::kInteger:
    case Type::kNumber: {
      const std::string s(text);
      char* end = nullptr;
      if (spec.type == Type::kInteger) {
        const long long v = std::strtoll(s.c_str(), &end, 10);
        if (!s.empty() && end && *end == '\0') j = static_cast<std::int64_t>(v);
      } else {
        const double v = std::strtod(s.c_str(), &end);
        if (!s.empty() && end && *end == '\0') j = v;
      }
      break;
    }
    case Type::kString: j = std::string(text); break;
  }
  return check_value(spec, j, "");
}

fs::path user_config_path() {
  if (const char* home = std::getenv("RIGEL_CONFIG_HOME"); home && *home) return fs::path(home) / "config.json";
  if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg) return fs::path(xdg) / "rigel" / "config.json";
  if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".config" / "rigel" / "config.json";
  return {};
}

const char* config_source_name(ConfigSource source) {
  switch (source) {
    case ConfigSource::kDefault: return "default";
    case ConfigSource::kUser: return "user";
    case ConfigSource::kProject: return "project";
  }
  return "default";
}

Config::Config() {
  for (const SettingSpec& s : setting_specs()) entries_.push_back({&s, s.fallback, ConfigSource::kDefault});
}

Result<Config> Config::load(const fs::path& user_file, const fs::path& project_file) {
  Config c;
  for (auto [file, source] : {std::pair{user_file, ConfigSource::kUser}, {project_file, ConfigSource::kProject}}) {
    Result<Json> settings = read_file(file);
    if (!settings) return settings.status();
    for (Entry& e : c.entries_) {
      if (!settings->contains(e.spec->key)) continue;
      e.value = *check_value(*e.spec, (*settings)[e.spec->key], file.string());
      e.source = source;
    }
    if (!file.empty()) log::debug("settings from " + file.string());
  }
  return c;
}

std::vector<Config::Entry> Config::list() const { return entries_; }

Result<Config::Entry> Config::get(std::string_view key) const {
  for (const Entry& e : entries_)
    if (e.spec->key == key) return e;
  return Status(ErrorCode::kNotFound, "no setting " + quote(key) + " (rigel config list shows them)").with_field("key");
}

std::string Config::string(std::string_view key) const {
  auto e = get(key);
  const std::string* s = e ? std::get_if<std::string>(&e->value) : nullptr;
  return s ? *s : std::string();
}
std::int64_t Config::integer(std::string_view key) const {
  auto e = get(key);
  const std::int64_t* v = e ? std::get_if<std::int64_t>(&e->value) : nullptr;
  return v ? *v : 0;
}
double Config::number(std::string_view key) const {
  auto e = get(key);
  const double* v = e ? std::get_if<double>(&e->value) : nullptr;
  return v ? *v : 0.0;
}
bool Config::flag(std::string_view key) const {
  auto e = get(key);
  const bool* v = e ? std::get_if<bool>(&e->value) : nullptr;
  return v && *v;
}

Status Config::set(const fs::path& file, std::string_view key, std::optional<std::string_view> value) {
  const SettingSpec* spec = find_setting(key);
  if (!spec) return Status(ErrorCode::kNotFound, "no setting " + quote(key) + " (rigel config list shows them)").with_field("key");
  if (file.empty()) return Status(ErrorCode::kInvalidArgument, "no settings file to write (set RIGEL_CONFIG_HOME or HOME)");
  Result<Json> settings = read_file(file);
  if (!settings) return settings.status();
  Json s = *settings;
  if (value) {
    Result<SettingValue> v = parse_setting(*spec, *value);
    if (!v) return v.status();
    std::visit([&](const auto& x) { s[spec->key] = x; }, *v);
  } else {
    s.erase(spec->key);
  }
  // Keys in the declared order, so the file diffs the same whichever was set first.
  Json ordered = Json::object();
  for (const SettingSpec& sp : setting_specs())
    if (s.contains(sp.key)) ordered[sp.key] = s[sp.key];
  std::error_code ec;
  if (file.has_parent_path()) fs::create_directories(file.parent_path(), ec);
  return io::write_file_atomic(file, io::diffable_json(Json{{"rigelConfig", kConfigFormat}, {"settings", ordered}}));
}

}  // namespace rigel::tools
