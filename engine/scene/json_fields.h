// Reading JSON input files field by field (the scene file, the model catalog): every failure is an
// InputError "FILE: FIELD: problem" naming the field path ("equipment[12].scale",
// "types.gauge.units"), unknown keys are errors (a typo must not fall back to a default silently),
// and so is a key given twice in one object (which nlohmann_json would resolve to its last value).
// Thread safety: pure functions (readJsonFile reads the file); a JsonFieldReader is immutable and
// its checks are const.
#pragma once

#include "nestwalk/core/input_error.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <vector>

namespace nestwalk {

/// "parent.key" ("key" at the root) and "parent[i]": the field paths errors name.
std::string joinField(const std::string& parent, const std::string& key);
std::string indexField(const std::string& parent, std::size_t i);

/// Parses `text` as JSON; throws InputError naming `file` for a syntax error (with its line and
/// column) or for a key repeated in one object (with its field path).
nlohmann::json parseJsonStrictly(const std::string& text, const std::string& file);

/// Reads a whole file as text; throws InputError naming it (`what`: "scene file", "catalog") when
/// it is absent, a folder or unreadable.
std::string readJsonFile(const std::string& path, const std::string& what);

/// Throws InputError "FILE: N model files not found: FIELD: PATH; ..." when `missing` (each
/// "FIELD: PATH") is not empty: every missing file in one error.
void failOnMissingModels(const std::string& file, const std::vector<std::string>& missing);

/// Field-by-field checks of a parsed document; relative paths resolve against `folder`.
class JsonFieldReader {
 public:
  JsonFieldReader(std::string file, std::filesystem::path folder) : file_(std::move(file)), folder_(std::move(folder)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& problem) const {
    throw InputError(file_ + ": " + (field.empty() ? "" : field + ": ") + problem);
  }

  void checkObject(const nlohmann::json& v, const std::string& field) const {
    if (!v.is_object()) fail(field, std::string("expected an object, got ") + v.type_name());
  }

  void checkKeys(const nlohmann::json& obj, const std::string& field, std::initializer_list<const char*> allowed) const {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      if (std::any_of(allowed.begin(), allowed.end(), [&](const char* a) { return it.key() == a; })) continue;
      std::string list;
      for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      fail(joinField(field, it.key()), "unknown key (expected one of: " + list + ")");
    }
  }

  double number(const nlohmann::json& v, const std::string& field) const {
    if (!v.is_number()) fail(field, std::string("expected a number, got ") + v.type_name());
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(field, "must be finite");
    return x;
  }
  double positive(const nlohmann::json& v, const std::string& field) const {
    const double x = number(v, field);
    if (!(x > 0)) fail(field, "must be > 0");
    return x;
  }
  double nonNegative(const nlohmann::json& v, const std::string& field) const {
    const double x = number(v, field);
    if (!(x >= 0)) fail(field, "must be >= 0");
    return x;
  }
  std::string string(const nlohmann::json& v, const std::string& field) const {
    if (!v.is_string()) fail(field, std::string("expected a string, got ") + v.type_name());
    return v.get<std::string>();
  }
  std::string nonEmptyString(const nlohmann::json& v, const std::string& field) const {
    std::string s = string(v, field);
    if (s.empty()) fail(field, "must not be empty");
    return s;
  }
  bool boolean(const nlohmann::json& v, const std::string& field) const {
    if (!v.is_boolean()) fail(field, std::string("expected true or false, got ") + v.type_name());
    return v.get<bool>();
  }
  /// An array of `minSize`..`maxSize` numbers.
  std::vector<double> numbers(const nlohmann::json& v, const std::string& field, std::size_t minSize, std::size_t maxSize) const {
    const std::string want = minSize == maxSize ? std::to_string(minSize) : std::to_string(minSize) + " or " + std::to_string(maxSize);
    if (!v.is_array()) fail(field, "expected an array of " + want + " numbers, got " + v.type_name());
    if (v.size() < minSize || v.size() > maxSize)
      fail(field, "expected " + want + " numbers, got " + std::to_string(v.size()));
    std::vector<double> out;
    for (std::size_t i = 0; i < v.size(); ++i) out.push_back(number(v[i], indexField(field, i)));
    return out;
  }
  /// Resolves a path written in the scene against the scene file's folder.
  std::string resolve(const std::string& p) const {
    const std::filesystem::path path(p);
    return (path.is_absolute() ? path : (folder_ / path)).lexically_normal().string();
  }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  std::filesystem::path folder_;
};

}  // namespace nestwalk
