#include "nestwalk/scene/json_fields.h"

#include <fstream>
#include <set>
#include <sstream>

namespace nestwalk {
namespace {

using Json = nlohmann::json;

/// Tracks the path of the value being parsed so that a key repeated in one object (which
/// nlohmann_json would silently resolve to its last value) is reported with its field path.
class DuplicateKeyTracker {
 public:
  bool operator()(int /*depth*/, Json::parse_event_t event, Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start:
        startElement();
        stack_.push_back({true, {}, {}, -1});
        break;
      case Json::parse_event_t::array_start:
        startElement();
        stack_.push_back({false, {}, {}, -1});
        break;
      case Json::parse_event_t::key: {
        Frame& top = stack_.back();
        const std::string key = parsed.get<std::string>();
        if (!top.keys.insert(key).second && firstDuplicate_.empty())
          firstDuplicate_ = joinField(path(stack_.size() - 1), key);
        top.key = key;
        break;
      }
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        stack_.pop_back();
        break;
      case Json::parse_event_t::value:
        startElement();
        break;
    }
    return true;
  }
  /// The field path of the first repeated key, empty when there was none.
  const std::string& firstDuplicate() const { return firstDuplicate_; }

 private:
  struct Frame {
    bool object;
    std::set<std::string> keys;
    std::string key;  // object: the key whose value is being parsed
    long index;       // array: the element being parsed
  };
  void startElement() {
    if (!stack_.empty() && !stack_.back().object) ++stack_.back().index;
  }
  std::string path(std::size_t frames) const {
    std::string p;
    for (std::size_t i = 0; i < frames; ++i) {
      const Frame& f = stack_[i];
      p = f.object ? joinField(p, f.key) : indexField(p, std::size_t(f.index));
    }
    return p;
  }
  std::vector<Frame> stack_;
  std::string firstDuplicate_;
};

}  // namespace

std::string joinField(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::string indexField(const std::string& parent, std::size_t i) { return parent + "[" + std::to_string(i) + "]"; }

Json parseJsonStrictly(const std::string& text, const std::string& file) {
  DuplicateKeyTracker duplicates;
  Json root;
  try {
    root = Json::parse(text, std::ref(duplicates));
  } catch (const Json::parse_error& e) {
    // e.what() reads "[json.exception.parse_error.101] parse error at line L, column C: ..."; keep
    // the part from "parse error" on (it names the line and column).
    std::string what = e.what();
    const std::size_t at = what.find("parse error");
    if (at != std::string::npos) what = what.substr(at);
    throw InputError(file + ": not valid JSON: " + what);
  } catch (const Json::exception& e) {
    // The parser's other refusals, e.g. out_of_range.406 for a number beyond double's range
    // ("number overflow parsing '164.04400E01752356'", found by the fuzzer).
    std::string what = e.what();
    const std::size_t at = what.find("] ");
    if (at != std::string::npos) what = what.substr(at + 2);
    throw InputError(file + ": not valid JSON: " + what);
  }
  if (!duplicates.firstDuplicate().empty()) throw InputError(file + ": " + duplicates.firstDuplicate() + ": duplicate key");
  return root;
}

void failOnMissingModels(const std::string& file, const std::vector<std::string>& missing) {
  if (missing.empty()) return;
  std::string list;
  for (const auto& m : missing) list += (list.empty() ? "" : "; ") + m;
  throw InputError(file + ": " + std::to_string(missing.size()) + " model file" + (missing.size() == 1 ? "" : "s") +
                   " not found: " + list);
}

std::string readJsonFile(const std::string& path, const std::string& what) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path + ": " + what + " not found");
  if (fs::is_directory(path, ec)) throw InputError(path + ": is a folder, not a " + what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the " + what);
  std::stringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path + ": cannot read the " + what);
  return ss.str();
}

}  // namespace nestwalk
