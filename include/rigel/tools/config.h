#pragma once
// Configuration (seed 004 §4.2, §4.7): settings with defaults, a user file
// and a project file, the project's overriding the user's overriding the
// defaults. Files are diffable JSON:
//
//   {
//     "rigelConfig": 1,
//     "settings": {
//       "log.level": "info"
//     }
//   }
//
// Every key is declared (setting_specs(): its type, default, allowed values
// and what it does); a file naming an unknown key, a value of the wrong
// type or out of range, or a newer format is refused naming the file (and
// line:column for malformed JSON), and nothing is changed.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "rigel/base/status.h"

namespace rigel::tools {

inline constexpr int kConfigFormat = 1;
// A project's settings file, in the project's folder.
inline constexpr const char* kProjectConfigFile = "rigel.config.json";

using SettingValue = std::variant<bool, std::int64_t, double, std::string>;

struct SettingSpec {
  std::string key;
  enum class Type { kBool, kInteger, kNumber, kString } type = Type::kString;
  SettingValue fallback;               // the default
  std::vector<std::string> choices;    // a string's allowed values (empty: any)
  double min = 0, max = 0;             // a number's or integer's range (min < max when set)
  std::string help;
};

// Every setting: log.level, naming.template, data.weights, viewport.menuMode,
// viewport.controlLineWidth, batch.jobs, batch.partition, publish.checks.
const std::vector<SettingSpec>& setting_specs();
const SettingSpec* find_setting(std::string_view key);

// The setting's value as text ("info", "2", "true"), and back: kInvalidArgument
// naming the key and what it takes for text it does not take.
std::string setting_text(const SettingValue& value);
Result<SettingValue> parse_setting(const SettingSpec& spec, std::string_view text);

// Where the user's settings live: $RIGEL_CONFIG_HOME/config.json, else
// $XDG_CONFIG_HOME/rigel/config.json, else $HOME/.config/rigel/config.json
// (empty when none of those is set).
std::filesystem::path user_config_path();

enum class ConfigSource { kDefault, kUser, kProject };
const char* config_source_name(ConfigSource source);  // "default", "user", "project"

class Config {
 public:
  // The settings of these files (either may be empty or missing: no
  // settings there). kParseError naming the file and place for a bad file.
  static Result<Config> load(const std::filesystem::path& user_file, const std::filesystem::path& project_file);
  // Defaults only.
  Config();

  struct Entry {
    const SettingSpec* spec = nullptr;
    SettingValue value;
    ConfigSource source = ConfigSource::kDefault;
  };
  // Every setting in setting_specs() order, with where its value came from.
  std::vector<Entry> list() const;
  // kNotFound naming "key" for an unknown key.
  Result<Entry> get(std::string_view key) const;
  // Typed reads of declared keys (the default when a key is not of the type).
  std::string string(std::string_view key) const;
  std::int64_t integer(std::string_view key) const;
  double number(std::string_view key) const;
  bool flag(std::string_view key) const;

  // Sets (or with no value, removes) `key` in `file`, checked against its
  // spec, keeping the file's other settings; written atomically, the file's
  // folder made. Errors name "key" or "value", or the file when it is bad.
  static Status set(const std::filesystem::path& file, std::string_view key, std::optional<std::string_view> value);

 private:
  std::vector<Entry> entries_;
};

}  // namespace rigel::tools
